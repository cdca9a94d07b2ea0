#pragma once
// How the window's sessions run, process-wide, from hapticbox-gui's command line.

/// --no-realtime, --spin-us, --timing (no hidden environment settings). Set before the first
/// session; read by the device (servo thread) and the session (open timing).
struct SessionRunSettings {
  bool realtime = true;   ///< ask for SCHED_FIFO for the servo thread.
  double spinUs = 0.0;    ///< servo busy-wait before each deadline, us (0: sleep only; the window renders on the same cores).
  bool timing = false;    ///< print where opening a model spends its time (stderr).
};

/// The process's settings (one instance; GUI thread).
inline SessionRunSettings& sessionRunSettings() {
  static SessionRunSettings settings;
  return settings;
}
