// A test's own directory: new and empty under the test temp dir, removed
// with everything in it when the test ends.
#pragma once

#include <gtest/gtest.h>
#include <stdlib.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>
#include <utility>

namespace raplas_test {

// A new empty directory under the test temp dir (empty path on failure).
inline std::filesystem::path make_temp_dir(const std::string& prefix) {
    std::string tmpl = (std::filesystem::path(::testing::TempDir()) / (prefix + "_XXXXXX")).string();
    if (!::mkdtemp(tmpl.data())) return {};
    return tmpl;
}

// A fixture whose tests each get such a directory, `dir`, named after
// `prefix` (a subclass's SetUp calls this one's first).
class TempDirFixture : public ::testing::Test {
protected:
    explicit TempDirFixture(std::string prefix) : prefix_(std::move(prefix)) {}
    std::filesystem::path dir;
    void SetUp() override {
        dir = make_temp_dir(prefix_);
        ASSERT_FALSE(dir.empty()) << "cannot create a temporary directory";
    }
    void TearDown() override {
        std::error_code ec;
        std::filesystem::remove_all(dir, ec);
    }
    // Writes `text` to the file `name` in the directory; returns its path.
    std::string write(const std::string& name, const std::string& text) const {
        const std::string p = (dir / name).string();
        std::ofstream(p, std::ios::binary) << text;
        return p;
    }

private:
    std::string prefix_;
};

}  // namespace raplas_test
