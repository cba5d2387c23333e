#include "mpm/core/interrupt.hpp"

#include <unistd.h>

#include <atomic>
#include <csignal>

namespace mpm {

namespace {
std::atomic<int> requested{0};
struct sigaction previous_int, previous_term;

extern "C" void on_signal(int signal) {
  int expected = 0;
  // A second signal: the user insists; end without writing anything more (only async-signal-safe calls here).
  if (!requested.compare_exchange_strong(expected, signal)) ::_exit(128 + signal);
}
}  // namespace

InterruptHandlers::InterruptHandlers() {
  requested = 0;
  struct sigaction action {};
  action.sa_handler = on_signal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESTART;  // a write in progress goes on; the run stops after its step
  sigaction(SIGINT, &action, &previous_int);
  sigaction(SIGTERM, &action, &previous_term);
}

InterruptHandlers::~InterruptHandlers() {
  sigaction(SIGINT, &previous_int, nullptr);
  sigaction(SIGTERM, &previous_term, nullptr);
}

int interrupt_requested() {
  return requested.load(std::memory_order_relaxed);
}

const char* signal_name(int signal) {
  return signal == SIGINT ? "SIGINT" : signal == SIGTERM ? "SIGTERM" : "signal";
}

}  // namespace mpm
