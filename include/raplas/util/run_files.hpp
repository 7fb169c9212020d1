// What a run reads and what it writes, checked before any work is done
// (docs/BAD_INPUT.md, "Rules"): every output can be written (its folder
// exists, it is no directory), no output is one of the inputs, and no two
// outputs are one file. Files are compared by device and inode when they
// exist (a link, a hard link or another spelling of the path is the same
// file) and by their resolved absolute paths otherwise.
#pragma once

#include <string>
#include <vector>

namespace raplas {

class RunFiles {
public:
    // `option` names where the path came from ("--json", "--scene", "mesh of
    // scene s.toml"); an empty path is ignored.
    void input(const std::string& option, const std::string& path);
    void output(const std::string& option, const std::string& path);
    // InputError naming the output and what it collides with.
    void check() const;

private:
    struct Entry {
        std::string option, path;
    };
    std::vector<Entry> inputs_, outputs_;
};

// True when a and b name one file (see above); false when either is empty.
bool same_file(const std::string& a, const std::string& b);

}  // namespace raplas
