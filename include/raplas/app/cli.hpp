// The `raplas` command line. Returns the process exit code:
// 0 success, 2 bad input or usage, 1 internal error.
#pragma once

namespace raplas {
int run_cli(int argc, char** argv);
}
