#pragma once
// Stopping on Ctrl-C (SIGINT) and SIGTERM, for the command line. Every command ends within
// StopDeadlineSeconds of the first signal with exit code 128 + signal (130, 143), whatever it is
// doing, and leaves no half-written file (write_atomically's temporaries are removed):
//   StopMode::Immediate  the first signal ends the process at once (commands that promise no
//                        partial output);
//   StopMode::Graceful   the first signal sets stop_flag(), which every long loop polls (through
//                        RenderOptions::interrupt), so that `render` writes what it has; a
//                        watchdog ends the process if it is still running at the deadline (a
//                        loop that does not poll: a BVH build, a scene still loading, a stuck
//                        computation). A second signal ends it at once.
// The library itself installs nothing: an embedding program (the Python module) passes a flag
// of its own in RenderOptions::interrupt.

#include <atomic>
#include <string>

namespace candela {

constexpr double StopDeadlineSeconds = 1.5;

enum class StopMode { Immediate, Graceful };

// Installs the SIGINT and SIGTERM handlers (first call) and sets what the first signal does.
void set_stop_mode(StopMode mode);
// Set by the first signal in Graceful mode.
const std::atomic<bool>& stop_flag();
// The first signal received, or 0.
int stop_signal();
// 128 + the first signal (the shell's convention), or 0 when none was received.
int stop_exit_code();

// A temporary file being written (write_atomically), removed if a signal ends the process before
// it is renamed into place. register_temporary returns a slot (or -1 when all are busy; the file
// is then left behind on such an exit).
int register_temporary(const std::string& path);
void unregister_temporary(int slot);

}  // namespace candela
