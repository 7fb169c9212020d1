// The shared scenes (../shared/scenes beside the checkout) in tests: a test
// that needs one is skipped, visibly, when it is missing, and fails instead
// under CI=true, where the scenes must be present.
#pragma once

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#ifndef RAPLAS_SHARED_SCENES
#error "RAPLAS_SHARED_SCENES must name the shared scenes folder (tests/CMakeLists.txt)"
#endif

namespace raplas_test {

inline bool in_ci() {
    const char* ci = std::getenv("CI");
    return ci && std::string(ci) == "true";
}

// A path under the shared scenes folder.
inline std::string shared_scene(const std::string& relative) { return std::string(RAPLAS_SHARED_SCENES) + "/" + relative; }

}  // namespace raplas_test

// In a test body: returns from the test, skipped, when `path` does not exist;
// under CI=true the test fails instead.
#define RAPLAS_NEED_SHARED(path)                                                                         \
    do {                                                                                                 \
        const std::string raplas_need_path_ = (path);                                                    \
        if (!std::filesystem::exists(raplas_need_path_)) {                                               \
            if (raplas_test::in_ci()) FAIL() << raplas_need_path_ << " is missing, and CI=true needs it"; \
            GTEST_SKIP() << raplas_need_path_ << " is missing";                                          \
        }                                                                                                \
    } while (0)
