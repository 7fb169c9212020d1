// Where raplas finds the files it ships, configs/ and scenes/: beside an
// installed executable (PREFIX/bin/raplas reads PREFIX/share/raplas), else in
// the source tree the build came from (a build tree). `--config paper` and
// `--scene bunny` are names looked up there.
#pragma once

#include <string>
#include <vector>

namespace raplas {

// The data folders, searched in this order: the installed one (found from
// /proc/self/exe) when it exists, then the source tree when it exists.
std::vector<std::string> data_dirs();

// Files a command names by kind: "config", folder "configs", listed by
// "raplas simulate --dump-config".
struct NamedFileKind {
    std::string what;    // "config", "scene"
    std::string folder;  // "configs", "scenes"
    std::string plural;  // "machine configs", "scene files": what is TOML
    std::string dump;    // the command that prints one
};

// The file `name` means: `name` itself when it exists; else, for a name
// without '/', FOLDER/NAME or FOLDER/NAME.toml in the working directory, then
// in each data folder. A name with '/' that does not exist is returned as
// given (reading it names the reason). Throws InputError for a YAML or JSON
// name (these are TOML) and for a name found nowhere, listing the names there
// are and the nearest ones.
std::string find_named_file(const std::string& name, const NamedFileKind& kind);

// The names (without .toml) of the TOML files in FOLDER of the working
// directory and of each data folder, sorted, each once.
std::vector<std::string> named_files(const std::string& folder);

}  // namespace raplas
