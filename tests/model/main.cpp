// The model tests run RUN_ALL_TESTS from our own main: libsystemc.so brings a
// main() of its own that would otherwise run no test at all.
#include <gtest/gtest.h>

#include <cstdlib>

extern "C" int sc_main(int, char**) { return 1; }

int main(int argc, char** argv) {
    ::setenv("SYSTEMC_DISABLE_COPYRIGHT_MESSAGE", "1", 0);
    ::testing::InitGoogleTest(&argc, argv);
    return RUN_ALL_TESTS();
}
