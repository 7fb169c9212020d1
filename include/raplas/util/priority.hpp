// Scheduling priority of the threads that work ahead of the timing model.
#pragma once

namespace raplas {

// Nice levels added to the threads that feed the timing model in a streamed
// run (the front end's threads, the trace reader, the next pass's preload).
// The model's own thread is the serial one; on a machine with fewer cores than
// runnable threads it would otherwise lose a fifth of its time to them
// (docs/PERFORMANCE.md, "The 1920x1080 frame"). They still take every cycle
// the model leaves idle.
constexpr int kFeederNice = 10;

// Lowers the calling thread's priority by `steps` nice levels (on Linux nice
// is per thread, and threads started afterwards inherit it). Best effort: a
// refusal is ignored, as nothing computed depends on it.
void lower_thread_priority(int steps);

}  // namespace raplas
