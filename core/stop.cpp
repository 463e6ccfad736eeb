#include "core/stop.h"

#include <signal.h>
#include <sys/time.h>
#include <unistd.h>

#include <cstring>

namespace candela {

namespace {

std::atomic<bool> g_stop{false};
std::atomic<int> g_signal{0};
std::atomic<int> g_mode{int(StopMode::Immediate)};
std::atomic<bool> g_installed{false};

// Temporaries to remove on a forced exit. A slot is Free, Claimed (being filled) or Ready; the
// signal handlers read only Ready slots. Everything here is async-signal-safe: atomics on
// lock-free ints, unlink, _exit.
constexpr int Slots = 8, PathBytes = 4096;
enum SlotState : int { Free, Claimed, Ready };
std::atomic<int> g_slot_state[Slots];
char g_slot_path[Slots][PathBytes];

[[noreturn]] void exit_now(int signal) {
    for (int i = 0; i < Slots; ++i)
        if (g_slot_state[i].load() == Ready) ::unlink(g_slot_path[i]);
    ::_exit(128 + signal);
}

void on_deadline(int) { exit_now(g_signal.load() ? g_signal.load() : SIGTERM); }

void on_stop_signal(int signal) {
    int expected = 0;
    const bool first = g_signal.compare_exchange_strong(expected, signal);
    if (!first || g_mode.load() == int(StopMode::Immediate)) exit_now(first ? signal : expected);
    g_stop.store(true);
    // The watchdog: SIGALRM at the deadline ends the process if the loops have not.
    itimerval deadline{};
    deadline.it_value.tv_sec = time_t(StopDeadlineSeconds);
    deadline.it_value.tv_usec = suseconds_t((StopDeadlineSeconds - double(time_t(StopDeadlineSeconds))) * 1e6);
    ::setitimer(ITIMER_REAL, &deadline, nullptr);
}

void install(int signal, void (*handler)(int)) {
    struct sigaction action;
    std::memset(&action, 0, sizeof action);
    action.sa_handler = handler;
    sigemptyset(&action.sa_mask);
    action.sa_flags = SA_RESTART;
    ::sigaction(signal, &action, nullptr);
}

}  // namespace

void set_stop_mode(StopMode mode) {
    g_mode.store(int(mode));
    if (g_installed.exchange(true)) return;
    install(SIGALRM, on_deadline);
    install(SIGINT, on_stop_signal);
    install(SIGTERM, on_stop_signal);
}

const std::atomic<bool>& stop_flag() { return g_stop; }
int stop_signal() { return g_signal.load(); }
int stop_exit_code() { return g_signal.load() ? 128 + g_signal.load() : 0; }

int register_temporary(const std::string& path) {
    if (path.size() + 1 > size_t(PathBytes)) return -1;
    for (int i = 0; i < Slots; ++i) {
        int expected = Free;
        if (!g_slot_state[i].compare_exchange_strong(expected, Claimed)) continue;
        std::memcpy(g_slot_path[i], path.c_str(), path.size() + 1);
        g_slot_state[i].store(Ready);
        return i;
    }
    return -1;
}

void unregister_temporary(int slot) {
    if (slot >= 0 && slot < Slots) g_slot_state[slot].store(Free);
}

}  // namespace candela
