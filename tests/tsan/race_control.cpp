// The negative control of scripts/tsan.sh: a deliberate data race between TBB tasks, built
// with the renderer's ThreadSanitizer flags and run with its suppressions (scripts/tsan.supp).
// TSan must report it, which shows that the suppressions for TBB's own bookkeeping do not
// hide a race in code that TBB tasks run. Not a test of the library; not built by CMake.
#include <chrono>
#include <cstdio>
#include <thread>

#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

int main() {
    long shared = 0;  // every task adds to it without synchronisation: the race
    const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 4);
    tbb::task_arena arena(4);
    arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range<int>(0, 64, 1), [&](const tbb::blocked_range<int>& r) {
            for (int i = r.begin(); i < r.end(); ++i) {
                std::this_thread::sleep_for(std::chrono::milliseconds(1));  // let other workers steal
                shared += i;
            }
        });
    });
    std::printf("race_control: %ld\n", shared);
    return 0;
}
