// Running raplas itself as child processes, and the shell words that name
// such a run in a job list (sweeps; any command that spreads one run over
// processes uses the same).
#pragma once

#include <sys/types.h>

#include <string>
#include <vector>

namespace raplas {

// `s` as one /bin/sh word (unquoted when it needs no quoting).
std::string shell_quote(const std::string& s);
std::string shell_join(const std::vector<std::string>& argv);
// The running executable's path (/proc/self/exe).
std::string self_exe();
// CPUs this process may run on.
unsigned core_count();
// "m:ss", or "h:mm:ss" from an hour on.
std::string format_duration(double seconds);
// Starts `raplas ARGS` (this very executable) with stdin and stdout on
// /dev/null and stderr into `log`; the child dies with its parent
// (PR_SET_PDEATHSIG), so a killed run leaves no workers. Block SIGCHLD
// around the calls to wait for it.
pid_t spawn_self(const std::vector<std::string>& args, const std::string& log);
// The last non-blank line of a text file ("" if none).
std::string last_line(const std::string& path);

}  // namespace raplas
