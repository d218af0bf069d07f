// render — a progress bar with ETA on stderr, drawn from its own thread once the work has
// taken a second.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <mutex>
#include <thread>

namespace render {

class Progress {
  public:
    Progress(std::size_t total, bool enabled);
    ~Progress();
    Progress(const Progress&) = delete;
    Progress& operator=(const Progress&) = delete;
    void add(std::size_t n) { done_ += n; }

  private:
    using Clock = std::chrono::steady_clock;
    void loop();
    void draw(std::size_t done) const;

    std::size_t total_;
    std::atomic<std::size_t> done_{0};
    Clock::time_point start_;
    std::mutex m_;
    std::condition_variable cv_;
    bool stop_ = false, drawn_ = false;
    std::thread thread_;
};

}  // namespace render
