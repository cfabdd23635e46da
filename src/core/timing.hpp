// Wall-clock timing of the kernel's parts (summary.json's timings_s).
#pragma once
#include <chrono>

namespace rpfem {

using Clock = std::chrono::steady_clock;

inline double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// Adds the seconds since t0 to `total` and restarts t0 (consecutive parts).
inline void lap(Clock::time_point& t0, double& total) {
  const auto now = Clock::now();
  total += std::chrono::duration<double>(now - t0).count();
  t0 = now;
}

// Adds the wall time of its scope to `total` (s).
class ScopedSeconds {
 public:
  explicit ScopedSeconds(double& total) : total_(total), t0_(Clock::now()) {}
  ~ScopedSeconds() { total_ += seconds_since(t0_); }
  ScopedSeconds(const ScopedSeconds&) = delete;
  ScopedSeconds& operator=(const ScopedSeconds&) = delete;

 private:
  double& total_;
  Clock::time_point t0_;
};

}  // namespace rpfem
