#include <sys/prctl.h>

#include <cstdlib>

#include "raplas/app/cli.hpp"

// libsystemc.so brings its own main() that calls sc_main(); ours takes
// precedence, and sc_main leads to the same place should it ever be used.
extern "C" int sc_main(int argc, char** argv) { return raplas::run_cli(argc, argv); }

int main(int argc, char** argv) {
    ::setenv("SYSTEMC_DISABLE_COPYRIGHT_MESSAGE", "1", 0);
    // The processes a run starts (sweep points, frames, --jobs shards) are
    // this executable run as /proc/self/exe, which names them "exe": named
    // "raplas" (ps, top, pkill), as the command is.
    ::prctl(PR_SET_NAME, "raplas", 0, 0, 0);
    return raplas::run_cli(argc, argv);
}
