#pragma once
// How long a stream has gone without a message, on the steady clock: what the nodelets' watchdogs
// name a stopped topic or a stalled device by. Arrivals may be marked on another thread than the one
// that asks.

#include <atomic>
#include <chrono>
#include <cstdint>

namespace vocal {

class StreamSilence {
 public:
  // A message arrived, or the stream was (re)started and its silence counts from now.
  void arrived() { last_ns_ = nowNanoseconds(); }
  bool heard() const { return last_ns_.load() != 0; }
  // Seconds since the last arrived(); 0 before the first.
  double seconds() const {
    const std::int64_t last = last_ns_.load();
    return last == 0 ? 0.0 : 1e-9 * static_cast<double>(nowNanoseconds() - last);
  }

 private:
  static std::int64_t nowNanoseconds() {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch()).count();
  }
  std::atomic<std::int64_t> last_ns_{0};
};

}  // namespace vocal
