// The examples' image output is atomic: a write that fails (a full disk, simulated with
// RLIMIT_FSIZE in a child process; an unwritable PNG path) leaves the previous EXR and PNG
// byte for byte as they were and no temporary file behind.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>

#include <common/image_io.hpp>

#if defined(__unix__) || defined(__APPLE__)
#include <csignal>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>
#define HAS_FORK 1
#endif

namespace io = hairscatter_examples;
namespace fs = std::filesystem;

namespace {

std::vector<char> bytes_of(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    return std::vector<char>((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
}

struct Image {
    int w, h;
    std::vector<float> rgb;
    std::vector<std::uint8_t> rgb8;
};

// A w × h image whose content depends on seed (so two writes differ).
Image image(int w, int h, int seed) {
    Image im{w, h, std::vector<float>(std::size_t(w * h * 3)), std::vector<std::uint8_t>(std::size_t(w * h * 3))};
    std::uint32_t s = std::uint32_t(seed) * 2654435761u + 1u;
    for (std::size_t i = 0; i < im.rgb.size(); ++i) {
        s = s * 1664525u + 1013904223u;
        im.rgb[i] = float(s >> 8) / float(1u << 24);
        im.rgb8[i] = io::srgb8(im.rgb[i]);
    }
    return im;
}

class ImageIo : public ::testing::Test {
  protected:
    void SetUp() override {
        dir_ = fs::path(::testing::TempDir()) / ("hairscatter_image_io_" + std::to_string(long(::getpid())));
        fs::remove_all(dir_);
        fs::create_directories(dir_);
        exr_ = (dir_ / "out.exr").string();
        png_ = (dir_ / "out.png").string();
        const Image a = image(32, 16, 1);
        io::write_exr_png_pair(exr_, png_, a.w, a.h, a.rgb, {{"note", "first"}}, a.rgb8);
        exr_bytes_ = bytes_of(exr_);
        png_bytes_ = bytes_of(png_);
        ASSERT_GT(exr_bytes_.size(), 100u);
        ASSERT_GT(png_bytes_.size(), 50u);
    }
    void TearDown() override { fs::remove_all(dir_); }

    // The first pair is still there, unchanged, and nothing else is in the directory.
    void expect_first_pair_intact() {
        EXPECT_EQ(bytes_of(exr_), exr_bytes_);
        EXPECT_EQ(bytes_of(png_), png_bytes_);
        int files = 0;
        for (const auto& e : fs::directory_iterator(dir_)) {
            ++files;
            EXPECT_TRUE(e.path().filename() == "out.exr" || e.path().filename() == "out.png") << e.path();
        }
        EXPECT_EQ(files, 2);
    }

    fs::path dir_;
    std::string exr_, png_;
    std::vector<char> exr_bytes_, png_bytes_;
};

TEST_F(ImageIo, SuccessfulWriteReplacesBoth) {
    const Image b = image(32, 16, 2);
    io::write_exr_png_pair(exr_, png_, b.w, b.h, b.rgb, {}, b.rgb8);
    EXPECT_NE(bytes_of(exr_), exr_bytes_);
    EXPECT_NE(bytes_of(png_), png_bytes_);
}

// The PNG cannot be written: the EXR written before it must not replace the old one.
TEST_F(ImageIo, FailedPngLeavesThePairAsItWas) {
    const Image b = image(32, 16, 2);
    const std::string bad_png = (dir_ / "missing_dir" / "out.png").string();
    EXPECT_THROW(io::write_exr_png_pair(exr_, bad_png, b.w, b.h, b.rgb, {}, b.rgb8), std::runtime_error);
    expect_first_pair_intact();
}

#if HAS_FORK
// A disk that fills up during the write (RLIMIT_FSIZE of 4 kB, SIGXFSZ ignored: writes
// fail with EFBIG as on a full disk), in a child process: every writer throws, and the
// previous files stay whole.
TEST_F(ImageIo, FullDiskLeavesThePreviousFiles) {
    const Image big = image(256, 256, 3);  // 786 kB of float EXR, far past 4 kB
    std::fflush(nullptr);
    const pid_t child = fork();
    if (child == 0) {
        std::signal(SIGXFSZ, SIG_IGN);
        const rlimit lim{4096, 4096};
        setrlimit(RLIMIT_FSIZE, &lim);
        int thrown = 0;
        try {
            io::write_exr_rgb(exr_, big.w, big.h, big.rgb, {});
        } catch (const std::runtime_error&) {
            ++thrown;
        }
        try {
            io::write_png_rgb8(png_, big.w, big.h, big.rgb8);
        } catch (const std::runtime_error&) {
            ++thrown;
        }
        try {
            io::write_exr_png_pair(exr_, png_, big.w, big.h, big.rgb, {}, big.rgb8);
        } catch (const std::runtime_error&) {
            ++thrown;
        }
        std::_Exit(thrown);
    }
    int status = 0;
    ASSERT_EQ(waitpid(child, &status, 0), child);
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 3) << "every write into the full disk must throw";
    expect_first_pair_intact();
}
#endif

}  // namespace
