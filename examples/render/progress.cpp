// render — the progress bar.
#include "progress.hpp"

#include <cstdio>

namespace render {

Progress::Progress(std::size_t total, bool enabled) : total_(total), start_(Clock::now()) {
    if (enabled) thread_ = std::thread([this] { loop(); });
}

Progress::~Progress() {
    {
        std::lock_guard<std::mutex> lock(m_);
        stop_ = true;
    }
    cv_.notify_all();
    if (thread_.joinable()) thread_.join();
    if (drawn_) {
        draw(total_);
        std::fputc('\n', stderr);
    }
}

void Progress::loop() {
    std::unique_lock<std::mutex> lock(m_);
    while (!cv_.wait_for(lock, std::chrono::milliseconds(250), [this] { return stop_; })) {
        if (std::chrono::duration<double>(Clock::now() - start_).count() < 1.0) continue;
        draw(done_.load());
        drawn_ = true;
    }
}

void Progress::draw(std::size_t done) const {
    const double t = std::chrono::duration<double>(Clock::now() - start_).count();
    const double f = total_ ? double(done) / double(total_) : 1.0;
    const int width = 30, filled = int(f * width);
    char bar[width + 1];
    for (int i = 0; i < width; ++i) bar[i] = i < filled ? '#' : '.';
    bar[width] = 0;
    const double eta = f > 0 ? t * (1 - f) / f : 0.0;
    std::fprintf(stderr, "\r[%s] %5.1f%%  %6.1f s  ETA %6.1f s ", bar, 100 * f, t, eta);
    std::fflush(stderr);
}

}  // namespace render
