// Hostile files and geometry (docs/robustness.md): the dual-table loader checks a file's
// size against its header before it reads or allocates the payload, the density grid
// refuses segments and boxes whose arithmetic leaves the float range, and the tabulated
// fiber validates its longitudinal table's size whichever M_p mode is chosen.
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include <hairscatter/dual.hpp>
#include <hairscatter/hairscatter.hpp>

namespace hs = hairscatter;

namespace {

// This process's peak resident set in bytes (VmHWM in /proc/self/status; 0 elsewhere).
std::size_t peak_rss_bytes() {
    std::ifstream f("/proc/self/status");
    std::string key;
    std::size_t kb = 0;
    while (f >> key)
        if (key == "VmHWM:" && (f >> kb)) return kb * 1024;
    return 0;
}

// The message of the exception f throws (of type E), or "" when it throws none.
template <typename E, typename F> std::string error_of(F&& f) {
    try {
        f();
    } catch (const E& e) {
        return e.what();
    }
    return "";
}

hs::DualScatteringTables<float> small_tables() {
    hs::DualTableOptions<float> o;
    o.theta_samples = 8;
    o.psi_samples = 9;
    o.h_nodes = 8;
    return hs::DualScatteringTables<float>::build<hs::ChiangFiber<float>>(hs::ChiangMaterial<float>(hs::FiberParams<float>{}), o);
}

// A valid table file followed by a 1 GiB sparse tail: refused from its size alone, in far
// less than a second and without reading the tail (it read and kept the whole GiB, 31 s).
TEST(DualTablesFile, OversizedFileIsRefusedBeforeItsPayloadIsRead) {
    const std::string path = ::testing::TempDir() + "hairscatter_oversized.hsdt";
    small_tables().save(path);
    const std::uintmax_t real = std::filesystem::file_size(path);
    std::filesystem::resize_file(path, std::uintmax_t(1) << 30);
    const std::size_t rss = peak_rss_bytes();
    const auto t0 = std::chrono::steady_clock::now();
    const std::string msg = error_of<std::runtime_error>([&] { hs::DualScatteringTables<float>::load(path); });
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::filesystem::remove(path);
    EXPECT_NE(msg.find("size 1073741824 bytes, expected " + std::to_string(real)), std::string::npos) << msg;
    EXPECT_LT(s, 0.5) << msg;
    EXPECT_LT(peak_rss_bytes() - rss, std::size_t(64) << 20) << "the peak resident set grew by " << peak_rss_bytes() - rss;
}

// A header promising the largest shape (65536 θ × 4 lobes × 65536 ψ: 412 GB) on a file of
// a few bytes: refused as truncated, nothing allocated for the promise.
TEST(DualTablesFile, UndersizedFileIsRefusedBeforeAllocating) {
    const std::string path = ::testing::TempDir() + "hairscatter_undersized.hsdt";
    small_tables().save(path);
    {
        std::fstream f(path, std::ios::binary | std::ios::in | std::ios::out);
        const std::uint32_t shape[3] = {65536, 65536, 4};  // θ samples, ψ samples, lobes
        f.seekp(8);
        f.write(reinterpret_cast<const char*>(shape), sizeof shape);
    }
    // (An attempt to allocate the promise would throw std::bad_alloc, not the refusal.)
    const std::string msg = error_of<std::runtime_error>([&] { hs::DualScatteringTables<float>::load(path); });
    EXPECT_NE(msg.find("(truncated?)"), std::string::npos) << msg;
    // The file as saved still loads, and a byte more or less is refused.
    small_tables().save(path);
    EXPECT_NO_THROW(hs::DualScatteringTables<float>::load(path));
    const std::uintmax_t real = std::filesystem::file_size(path);
    std::filesystem::resize_file(path, real + 1);
    EXPECT_NE(error_of<std::runtime_error>([&] { hs::DualScatteringTables<float>::load(path); })
                  .find("expected " + std::to_string(real)),
              std::string::npos);
    std::filesystem::resize_file(path, real - 1);
    EXPECT_NE(error_of<std::runtime_error>([&] { hs::DualScatteringTables<float>::load(path); }).find("(truncated?)"),
              std::string::npos);
    std::filesystem::remove(path);
}

// A stream whose size is unknown (a pipe) is read up to what the header promises and no
// further: its 1 MiB tail is reported without being read whole.
TEST(DualTablesFile, StreamsOfUnknownSizeAreBoundedByTheHeader) {
    const std::string file = ::testing::TempDir() + "hairscatter_piped.hsdt";
    small_tables().save(file);
    // One pipe each: the first writer may still hold its pipe open after the reader left.
    const std::string longer = ::testing::TempDir() + "hairscatter_piped_longer.fifo",
                      whole = ::testing::TempDir() + "hairscatter_piped_whole.fifo";
    for (const std::string& fifo : {longer, whole}) {
        std::filesystem::remove(fifo);
        if (std::system(("mkfifo " + fifo).c_str()) != 0) GTEST_SKIP() << "no mkfifo";
    }
    // The writer: the file, then a tail; it ends when the reader closes the pipe.
    const std::string writer = "(cat " + file + "; head -c 1048576 /dev/zero) > " + longer + " 2>/dev/null &";
    ASSERT_EQ(std::system(writer.c_str()), 0);
    const std::string msg = error_of<std::runtime_error>([&] { hs::DualScatteringTables<float>::load(longer); });
    EXPECT_NE(msg.find("longer than the " + std::to_string(std::filesystem::file_size(file))), std::string::npos) << msg;
    // And a whole file through a pipe loads.
    ASSERT_EQ(std::system(("cat " + file + " > " + whole + " &").c_str()), 0);
    EXPECT_NO_THROW(hs::DualScatteringTables<float>::load(whole));
    for (const std::string& path : {longer, whole, file}) std::filesystem::remove(path);
}

template <typename T> bool all_cells_finite(const hs::DensityGrid<T>& g) {
    for (const auto& c : g.cells())
        if (!std::isfinite(c.length())) return false;
    return std::isfinite(g.total_length());
}

// A segment to the largest float: its length overflows, and the deposit was +Inf with NaN
// in the cells' orientation. Refused, naming the call and its ends; the grid is unchanged.
template <typename T> void check_overflowing_segments() {
    using V3 = glm::vec<3, T>;
    const T big = std::numeric_limits<T>::max();
    hs::DensityGrid<T> g(V3(0), V3(1), glm::ivec3(4), T(0.01));
    for (const auto& ends : std::vector<std::pair<V3, V3>>{{V3(T(0.5)), V3(big, T(0.5), T(0.5))},
                                                             {V3(-big, T(0.5), T(0.5)), V3(big, T(0.5), T(0.5))},
                                                             {V3(T(0.5)), V3(big)},
                                                             {V3(T(0.5)), V3(T(2) * std::sqrt(big), T(0.5), T(0.5))}}) {
        // (Not a structured binding: C++17 lambdas cannot capture one, and Clang refuses.)
        const std::string msg = error_of<std::invalid_argument>([&] { g.add_segment(ends.first, ends.second); });
        EXPECT_NE(msg.find("DensityGrid::add_segment"), std::string::npos) << msg;
        EXPECT_NE(msg.find("length"), std::string::npos) << msg;
    }
    EXPECT_TRUE(all_cells_finite(g));
    EXPECT_EQ(g.total_length(), T(0));
    // Long but representable segments still deposit their part inside the box.
    EXPECT_NEAR(double(g.add_segment(V3(T(0.5)), V3(T(1e15), T(0.5), T(0.5)))), 0.5, 1e-6);
    EXPECT_TRUE(all_cells_finite(g));
    // Non-finite ends stay skipped (a strand with a NaN point loses that segment only).
    EXPECT_EQ(g.add_segment(V3(std::numeric_limits<T>::quiet_NaN()), V3(T(0.5))), T(0));
}

TEST(DensityGridRange, OverflowingSegmentsAreRefused) {
    check_overflowing_segments<float>();
    check_overflowing_segments<double>();
}

// Boxes whose cells are too small or too large for T: a 1e-38 box gave NaN densities. Each
// is refused naming the box; boxes well inside the range answer finite densities.
TEST(DensityGridRange, BoxesOutsideTheFloatRangeAreRefused) {
    using V3 = glm::vec3;
    const float big = std::numeric_limits<float>::max();
    auto refused = [](const V3& lo, const V3& hi, const glm::ivec3& res, const std::string& named) {
        const std::string msg = error_of<std::invalid_argument>([&] { hs::DensityGrid<float>(lo, hi, res, 0.01f); });
        EXPECT_NE(msg.find(named), std::string::npos) << "box " << hi.x - lo.x << ": " << msg;
    };
    refused(V3(0), V3(1e-38f), glm::ivec3(1), "cell size");      // a subnormal side
    refused(V3(0), V3(1e-38f), glm::ivec3(4), "cell size");
    refused(V3(0), V3(1e-20f), glm::ivec3(1), "cell volume");    // sides fine, the volume underflows
    refused(V3(0), V3(1e-12f), glm::ivec3(2), "cell volume");    // a density's square overflows
    refused(V3(0), V3(1e8f), glm::ivec3(2), "cell volume");      // … or underflows
    refused(V3(0), V3(1e20f), glm::ivec3(1), "cell volume");     // the volume overflows
    refused(V3(-big), V3(big), glm::ivec3(1), "box_max.x - box_min.x");  // the extent overflows
    refused(V3(0), V3(1e20f, 1, 1), glm::ivec3(1), "diagonal");  // its square overflows
    for (float side : {1e-5f, 1e5f}) {
        hs::DensityGrid<float> g(V3(0), V3(side), glm::ivec3(2), 0.25f * side);
        g.add_segment(V3(0.1f * side), V3(0.9f * side));
        const float l = g.length_density(V3(0.5f * side)), c = g.crossing_density(V3(0.5f * side), V3(1, 0, 0)),
                    n = g.fibers_crossed(V3(0.5f * side, 0.5f * side, -side), V3(0, 0, 1), 10.0f * side);
        EXPECT_TRUE(std::isfinite(l) && l > 0 && std::isfinite(c) && std::isfinite(n)) << side << ": " << l << " " << c << " " << n;
    }
}

// m_rows and m_nodes are checked in exact mode too (0 and 1e9 used to pass there while
// fast() refused them): an option is valid or not whatever the mode.
TEST(TabulatedOptionsRange, LongitudinalTableSizeIsCheckedInBothModes) {
    const hs::FiberParams<double> p;
    for (hs::TabulatedOptions o : {hs::TabulatedOptions::coarse(), hs::TabulatedOptions::fast()}) {
        o.phi_samples = 8;
        o.theta_samples = 4;
        o.h_nodes = 8;
        for (int bad : {0, 1, -3, 1000000000}) {
            hs::TabulatedOptions r = o, n = o;
            r.m_rows = bad;
            n.m_nodes = bad;
            const std::string mr = error_of<std::invalid_argument>([&] { hs::TabulatedMaterial<double>(p, r); });
            const std::string mn = error_of<std::invalid_argument>([&] { hs::TabulatedMaterial<double>(p, n); });
            EXPECT_NE(mr.find("TabulatedOptions::m_rows = " + std::to_string(bad)), std::string::npos) << mr;
            EXPECT_NE(mn.find("TabulatedOptions::m_nodes = " + std::to_string(bad)), std::string::npos) << mn;
        }
        EXPECT_NO_THROW(hs::TabulatedMaterial<double>(p, o));
    }
}

}  // namespace
