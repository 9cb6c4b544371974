#pragma once
// Progress of a long run: step, simulated time, steps per second and the
// estimated time left. On a terminal one line updated in place ('\r', at most
// five times a second); in a log (not a terminal) a plain line at a cadence
// of wall-clock seconds, so logs stay short.
#include <chrono>
#include <cstdio>
#include <string>

namespace fdem {

/// One progress line, e.g.
/// "step 1200  t = 0.012 s of 1 s (1.2%)  340 steps/s  left 0:04:51".
/// eta_s < 0 prints "left ?".
std::string format_progress(long long step, double time_s, double end_time_s, double steps_per_s, double eta_s);

/// h:mm:ss for a duration in seconds.
std::string format_duration(double seconds);

class ProgressReporter {
 public:
  /// `terminal`: update one line in place; otherwise print a line every
  /// `log_interval_s` wall seconds. `out` may be null (quiet).
  ProgressReporter(std::FILE* out, double end_time_s, bool terminal, double log_interval_s = 10.0);

  /// Whether `stream` is a terminal (isatty).
  static bool is_terminal(std::FILE* stream);

  /// After each step; reads the steady clock.
  void update(long long step, double time_s);
  /// The same with the wall time given (seconds since start), for tests.
  void update_at(long long step, double time_s, double wall_s);
  /// Final line (always printed, ends the terminal line).
  void finish(long long step, double time_s);
  void finish_at(long long step, double time_s, double wall_s);

  /// Recent rates, as last printed.
  double steps_per_second() const { return steps_per_s_; }
  double eta_seconds() const { return eta_s_; }
  int lines_printed() const { return lines_; }

 private:
  void print(long long step, double time_s, bool final_line);
  double wall_now() const;

  std::FILE* out_;
  double end_time_s_;
  bool terminal_;
  double interval_s_;
  std::chrono::steady_clock::time_point start_;
  // Last sample the rates were measured from.
  bool have_sample_ = false;
  long long last_step_ = 0;
  double last_time_s_ = 0.0, last_wall_s_ = 0.0, last_print_wall_s_ = -1e300;
  double steps_per_s_ = 0.0, sim_per_wall_ = 0.0, eta_s_ = -1.0;
  int lines_ = 0;
  std::size_t last_width_ = 0;
};

}  // namespace fdem
