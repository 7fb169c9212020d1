// fuzz_config: machine configs (ParamSet::load_text on machine_params(), then
// config_from_params). dump() must print TOML that reads back to the same
// values.
#include <string>

#include "config.hpp"
#include "fuzz_common.hpp"

// config.cpp includes SystemC, so libsystemc.so (whose main() needs an
// sc_main) is linked; libFuzzer's main() is the one that runs.
extern "C" int sc_main(int, char**) { return 1; }

namespace {

const char* const kTarget = "fuzz_config";

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const unsigned char* data, std::size_t size) {
    const std::string text = raplas::fuzz::as_string(data, size);
    raplas::ParamSet p = raplas::model::machine_params();
    if (!raplas::fuzz::guarded(kTarget, [&] { p.load_text(text, "fuzz.toml"); })) return 0;
    raplas::fuzz::check_dump(kTarget, p, raplas::model::machine_params());
    raplas::fuzz::guarded(kTarget, [&] {
        const raplas::model::SimConfig c = raplas::model::config_from_params(p);
        if (c.iccs < 1 || c.icc.sphere_fifo.depth < 1 || c.icc.triangle_fifo.depth < 1 || c.sync_cycles < 1 ||
            c.watchdog_cycles < 1 || !(c.clock_mhz > 0))
            raplas::fuzz::fail(kTarget, "config value out of its declared range");
    });
    return 0;
}
