// The unit tests link raplas_app, which brings libsystemc.so and its own
// main(); with our main here, no link order can make the binary run zero tests.
#include <gtest/gtest.h>

#include <cstdio>

extern "C" int sc_main(int, char**) { return 1; }

int main(int argc, char** argv) {
    // The bad-input table runs raplas in forked children of this binary; a
    // sweep that got past its checks would spawn this binary as raplas
    // ("trace ...", "simulate ..."), and each copy would run the table again.
    // Such a child ends at once instead, and the case fails.
    if (argc > 1 && argv[1][0] != '-') {
        std::fprintf(stderr, "%s: started as raplas (%s ...): these are the unit tests\n", argv[0], argv[1]);
        return 125;
    }
    ::testing::InitGoogleTest(&argc, argv);
    return RUN_ALL_TESTS();
}
