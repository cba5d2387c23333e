#pragma once
/// SIGINT and SIGTERM during a run: the first asks the run to stop after its current step (it then writes a
/// checkpoint and its summary); a second ends the program at once with exit status 128 + the signal.
namespace mpm {

/// Installs the handlers while it lives and restores the previous ones after; clears any earlier request.
class InterruptHandlers {
 public:
  InterruptHandlers();
  ~InterruptHandlers();
  InterruptHandlers(const InterruptHandlers&) = delete;
  InterruptHandlers& operator=(const InterruptHandlers&) = delete;
};

/// The signal that asked the run to stop (SIGINT or SIGTERM), or 0.
int interrupt_requested();

/// Its name, "SIGINT" or "SIGTERM".
const char* signal_name(int signal);

}  // namespace mpm
