// The unit tests link raplas_app, which brings libsystemc.so and its own
// main(); with our main here, no link order can make the binary run zero tests.
#include <gtest/gtest.h>

extern "C" int sc_main(int, char**) { return 1; }

int main(int argc, char** argv) {
    ::testing::InitGoogleTest(&argc, argv);
    return RUN_ALL_TESTS();
}
