// read_text_input: files the user names, whatever they are (regular files,
// pipes, devices, /proc files), read to their end or refused with one line.
#include <fcntl.h>
#include <unistd.h>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <csignal>
#include <cstdlib>
#include <string>
#include <thread>

#include "raplas/util/error.hpp"
#include "raplas/util/input_file.hpp"

using namespace raplas;
using ::testing::HasSubstr;
using ::testing::StartsWith;

namespace {

const TextInput kObj{"OBJ file", "an", "OBJ text", 3.0};

std::string error_of(const std::string& path, const TextInput& kind = kObj) {
    try {
        read_text_input(path, kind);
    } catch (const InputError& e) {
        return e.what();
    }
    return "(read without error)";
}

// A pipe whose writer thread writes `line` until `limit` bytes are written
// (0: until the reading end is closed), then closes its end.
struct Pipe {
    int fds[2] = {-1, -1};
    std::thread writer;
    void (*old_handler)(int) = nullptr;
    Pipe(const std::string& line, std::size_t limit) {
        old_handler = std::signal(SIGPIPE, SIG_IGN);  // a closed reader gives EPIPE
        EXPECT_EQ(::pipe(fds), 0);
        writer = std::thread([this, line, limit] {
            std::string block;
            while (block.size() < (1 << 16)) block += line;
            std::size_t written = 0;
            while (limit == 0 || written < limit) {
                const std::size_t n = limit == 0 ? block.size() : std::min(block.size(), limit - written);
                const ssize_t w = ::write(fds[1], block.data(), n);
                if (w <= 0) break;
                written += std::size_t(w);
            }
            ::close(fds[1]);
        });
    }
    std::string path() const { return "/dev/fd/" + std::to_string(fds[0]); }
    ~Pipe() {
        ::close(fds[0]);
        writer.join();
        std::signal(SIGPIPE, old_handler);
    }
};

TEST(InputFile, ReadsAPipeToItsEnd) {
    const std::size_t size = 200000;  // several reads
    std::string text;
    {
        Pipe p("v 0 0 0\n", size);
        text = read_text_input(p.path(), kObj);
    }
    ASSERT_EQ(text.size(), size);
    EXPECT_EQ(text.substr(0, 16), "v 0 0 0\nv 0 0 0\n");
}

TEST(InputFile, AFileThatSaysItIsEmptyIsReadAsAStream) {
    // /proc files are regular files of size 0
    EXPECT_THAT(read_text_input("/proc/self/status", kObj), HasSubstr("Name:"));
}

TEST(InputFile, DevicesThatNeverEndStopAtTheFirstNul) {
    EXPECT_EQ(error_of("/dev/zero"), "/dev/zero: not a text OBJ file (contains NUL bytes)");
    EXPECT_EQ(error_of("/dev/urandom", {"scene file", "a", "TOML text", 32.0}),
              "/dev/urandom: not a text scene file (contains NUL bytes)");
}

TEST(InputFile, AStreamThatNeverEndsIsRefusedByTheMemoryBudget) {
    ::setenv("RAPLAS_MAX_MEMORY", "100M", 1);
    std::string err;
    {
        Pipe p("v 0 0 0\n", 0);
        err = error_of(p.path());
    }
    ::unsetenv("RAPLAS_MAX_MEMORY");
    // refused at the first check, after 64 MiB: 3 x 64 MiB counted
    EXPECT_THAT(err, StartsWith("loading /dev/fd/"));
    EXPECT_THAT(err, HasSubstr("(OBJ text: 192 MiB"));
    EXPECT_THAT(err, HasSubstr("100 MiB is available (RAPLAS_MAX_MEMORY)"));
}

TEST(InputFile, MissingFilesAndDirectoriesAreNamed) {
    EXPECT_EQ(error_of("/nonexistent/x.obj"), "/nonexistent/x.obj: cannot open OBJ file: No such file or directory");
    EXPECT_EQ(error_of("/tmp", {"scene file", "a", "TOML text", 32.0}), "/tmp: is a directory, not a scene file");
}

}  // namespace
