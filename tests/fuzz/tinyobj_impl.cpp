// tinyobjloader's implementation, compiled into fuzz_obj so that the
// sanitizers and the fuzzer's coverage see it (the Debian shared library is
// not instrumented); the executable's definitions take precedence over the
// library's.
#define TINYOBJLOADER_IMPLEMENTATION
#include <tiny_obj_loader.h>
