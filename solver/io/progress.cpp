#include "io/progress.hpp"

#include <unistd.h>

#include <cmath>

#include <fmt/format.h>

namespace fdem {

std::string format_duration(double seconds) {
  if (!(seconds >= 0.0) || !std::isfinite(seconds)) return "?";
  const auto total = static_cast<long long>(std::llround(seconds));
  return fmt::format("{}:{:02}:{:02}", total / 3600, (total / 60) % 60, total % 60);
}

std::string format_progress(long long step, double time_s, double end_time_s, double steps_per_s, double eta_s) {
  const double percent = end_time_s > 0.0 ? 100.0 * time_s / end_time_s : 0.0;
  return fmt::format("step {}  t = {:.6g} s of {:.6g} s ({:.1f}%)  {:.3g} steps/s  left {}", step, time_s, end_time_s,
                     percent, steps_per_s, eta_s < 0.0 ? std::string("?") : format_duration(eta_s));
}

ProgressReporter::ProgressReporter(std::FILE* out, double end_time_s, bool terminal, double log_interval_s)
    : out_(out),
      end_time_s_(end_time_s),
      terminal_(terminal),
      // A terminal line redraws at most 5 times a second: cheap, still live.
      interval_s_(terminal ? 0.2 : log_interval_s),
      start_(std::chrono::steady_clock::now()) {}

bool ProgressReporter::is_terminal(std::FILE* stream) { return stream != nullptr && ::isatty(::fileno(stream)) == 1; }

double ProgressReporter::wall_now() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

void ProgressReporter::update(long long step, double time_s) { update_at(step, time_s, wall_now()); }

void ProgressReporter::update_at(long long step, double time_s, double wall_s) {
  if (!have_sample_) {
    // The first call only starts the clock: one step says nothing about the rate.
    have_sample_ = true;
    last_step_ = step;
    last_time_s_ = time_s;
    last_wall_s_ = wall_s;
    last_print_wall_s_ = wall_s;
    return;
  }
  if (wall_s - last_print_wall_s_ < interval_s_) return;
  const double dt_wall = wall_s - last_wall_s_;
  if (dt_wall > 0.0) {
    // Rates over the window since the last line, smoothed (weight 1/2) so the
    // estimate follows a change in cost without jumping on every redraw.
    const double steps_rate = static_cast<double>(step - last_step_) / dt_wall;
    const double sim_rate = (time_s - last_time_s_) / dt_wall;
    const bool first = steps_per_s_ == 0.0;
    steps_per_s_ = first ? steps_rate : 0.5 * (steps_per_s_ + steps_rate);
    sim_per_wall_ = first ? sim_rate : 0.5 * (sim_per_wall_ + sim_rate);
    eta_s_ = sim_per_wall_ > 0.0 ? std::max(0.0, end_time_s_ - time_s) / sim_per_wall_ : -1.0;
  }
  last_step_ = step;
  last_time_s_ = time_s;
  last_wall_s_ = wall_s;
  last_print_wall_s_ = wall_s;
  print(step, time_s, false);
}

void ProgressReporter::finish(long long step, double time_s) { finish_at(step, time_s, wall_now()); }

void ProgressReporter::finish_at(long long step, double time_s, double wall_s) {
  steps_per_s_ = wall_s > 0.0 ? static_cast<double>(step) / wall_s : 0.0;  // the whole run's average
  eta_s_ = 0.0;
  print(step, time_s, true);
}

void ProgressReporter::print(long long step, double time_s, bool final_line) {
  ++lines_;
  if (out_ == nullptr) return;
  const std::string line = format_progress(step, time_s, end_time_s_, steps_per_s_, eta_s_);
  if (terminal_) {
    // Pad over the previous, longer line; the final line ends with a newline.
    const std::size_t pad = last_width_ > line.size() ? last_width_ - line.size() : 0;
    std::fprintf(out_, "\r%s%*s%s", line.c_str(), static_cast<int>(pad), "", final_line ? "\n" : "");
    last_width_ = line.size();
  } else {
    std::fprintf(out_, "%s\n", line.c_str());
  }
  std::fflush(out_);
}

}  // namespace fdem
