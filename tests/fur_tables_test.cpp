// FurMaterial's medulla table file (models/fur.hpp, save/load): the tables come back bit for
// bit in float and double, the roughness may differ from the saved material's with the smooth
// cortex (not with the rough one, whose tables depend on it), and a file
// of another version, table size or length, a corrupt one, one with a value out of range
// and one built for other parameters are refused with an error naming the file and why.
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include <hairscatter/models/fur.hpp>

namespace hs = hairscatter;

namespace {

template <typename T> hs::FurParams<T> medulla_params() {
    hs::FurParams<T> p;
    p.cortex.sigma_a = glm::vec<3, T>(T(0.5447), T(0.9061), T(1.781));
    p.kappa = T(0.6);
    p.sigma_s = T(10);
    p.sigma_a_medulla = glm::vec<3, T>(T(0.1), T(0.2), T(0.3));
    p.g = T(0.3);
    return p;
}

std::string temp_path(const char* name) { return ::testing::TempDir() + name; }

std::vector<unsigned char> read_bytes(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    return std::vector<unsigned char>(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
}

void write_bytes(const std::string& path, const std::vector<unsigned char>& b) {
    std::ofstream f(path, std::ios::binary | std::ios::trunc);
    f.write(reinterpret_cast<const char*>(b.data()), std::streamsize(b.size()));
}

// The file's checksum recomputed, so that only the check under test can refuse it.
void reseal(std::vector<unsigned char>& b) {
    const std::uint64_t sum = hs::detail::fnv1a(b.data(), b.size() - 8);
    std::memcpy(b.data() + b.size() - 8, &sum, 8);
}

template <typename T> void round_trip_is_bit_identical() {
    const hs::FurMaterial<T> built(medulla_params<T>());
    const std::string path = temp_path("hairscatter_fur_round_trip.hsft");
    built.save(path);
    const hs::FurMaterial<T> loaded = hs::FurMaterial<T>::load(medulla_params<T>(), path);
    EXPECT_EQ(std::memcmp(&built.medulla(), &loaded.medulla(), sizeof(hs::MedullaTables<T>)), 0);
    // The same tables, so the same fibre: eval and sample agree exactly.
    const glm::vec<3, T> wo = glm::normalize(glm::vec<3, T>(T(0.3), T(0.8), T(0.2)));
    const glm::vec<3, T> wi = glm::normalize(glm::vec<3, T>(T(-0.2), T(-0.5), T(0.7)));
    const hs::FurFiber<T> a(built, T(0.37)), b(loaded, T(0.37));
    EXPECT_EQ(a.eval(wo, wi), b.eval(wo, wi));
    EXPECT_EQ(a.pdf(wo, wi), b.pdf(wo, wi));
}

// load(params, bytes) must throw std::runtime_error whose message names the file and holds
// `why`.
void expect_refused(const std::vector<unsigned char>& bytes, const std::string& why,
                    const hs::FurParams<double>& params = medulla_params<double>()) {
    const std::string path = temp_path("hairscatter_fur_bad.hsft");
    write_bytes(path, bytes);
    try {
        hs::FurMaterial<double>::load(params, path);
        ADD_FAILURE() << "accepted a file expected to fail with '" << why << "'";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find(why), std::string::npos) << e.what();
    }
}

}  // namespace

TEST(FurTables, RoundTripIsBitIdenticalFloat) { round_trip_is_bit_identical<float>(); }
TEST(FurTables, RoundTripIsBitIdenticalDouble) { round_trip_is_bit_identical<double>(); }

// With the smooth cortex β_m, β_n and α do not enter the tables: a file serves every roughness.
TEST(FurTables, LoadTakesTheGivenRoughness) {
    const std::string path = temp_path("hairscatter_fur_roughness.hsft");
    hs::FurMaterial<double>(medulla_params<double>()).save(path);
    hs::FurParams<double> rough = medulla_params<double>();
    rough.cortex.beta_m = 0.6;
    rough.cortex.beta_n = 0.5;
    const hs::FurMaterial<double> m = hs::FurMaterial<double>::load(rough, path);
    EXPECT_EQ(m.params().cortex.beta_m, 0.6);
    EXPECT_EQ(m.params().cortex.beta_n, 0.5);
}

// With the rough cortex the tables depend on its facets (α, β_m, β_n, facet α) as well: its
// file loads back bit for bit for the same parameters, and is refused for another β_m, α or
// facet α, for the smooth cortex, and a smooth cortex's file for the rough one, naming the
// parameter.
TEST(FurTables, RoughCortexTablesKeepTheirRoughness) {
    const std::string path = temp_path("hairscatter_fur_rough.hsft");
    hs::FurParams<double> rough = medulla_params<double>();
    rough.rough_cortex = true;
    const hs::FurMaterial<double> built(rough);
    built.save(path);
    const hs::FurMaterial<double> loaded = hs::FurMaterial<double>::load(rough, path);
    EXPECT_EQ(std::memcmp(&built.medulla(), &loaded.medulla(), sizeof(hs::MedullaTables<double>)), 0);
    const std::vector<unsigned char> bytes = read_bytes(path);
    hs::FurParams<double> other = rough;
    other.cortex.beta_m = 0.6;
    expect_refused(bytes, "beta_m", other);
    other = rough;
    other.cortex.alpha = 0.1;
    expect_refused(bytes, "alpha", other);
    other = rough;
    other.facet_alpha = 0.17;
    expect_refused(bytes, "facet_alpha", other);
    expect_refused(bytes, "rough_cortex", medulla_params<double>());
    hs::FurMaterial<double>(medulla_params<double>()).save(path);
    expect_refused(read_bytes(path), "rough_cortex", rough);
}

TEST(FurTables, RejectsBadFilesNamingThem) {
    const std::string path = temp_path("hairscatter_fur_good.hsft");
    hs::FurMaterial<double>(medulla_params<double>()).save(path);
    const std::vector<unsigned char> good = read_bytes(path);
    ASSERT_GT(good.size(), 200u);
    EXPECT_NO_THROW(hs::FurMaterial<double>::load(medulla_params<double>(), path));

    auto with_u32 = [&](std::size_t at, std::uint32_t v) {
        std::vector<unsigned char> b = good;
        std::memcpy(b.data() + at, &v, 4);
        reseal(b);
        return b;
    };
    expect_refused(with_u32(4, 1), "version 1, this library reads version 6");
    expect_refused(with_u32(8, 7), "tables of 7 x 32 bins");
    expect_refused(with_u32(12, 16), "tables of 6 x 16 bins");
    expect_refused(std::vector<unsigned char>(good.begin(), good.end() - 9), "truncated");
    std::vector<unsigned char> longer = good;
    longer.push_back(0);
    expect_refused(longer, "longer than");
    std::vector<unsigned char> magic = good;
    magic[0] = 'X';
    expect_refused(magic, "bad magic");
    expect_refused(std::vector<unsigned char>(good.begin(), good.begin() + 10), "bad magic or too short");
    std::vector<unsigned char> flipped = good;
    flipped[200] ^= 0x10;
    expect_refused(flipped, "checksum");
    // The first density value (after magic, three sizes and fifteen parameters), negative.
    std::vector<unsigned char> negative = good;
    const double minus_one = -1.0;
    std::memcpy(negative.data() + 4 + 3 * 4 + 15 * 8, &minus_one, 8);
    reseal(negative);
    expect_refused(negative, "a density value = -1");
    // The first bin's longitudinal skew (after its 32 densities, 33 cdf values, 3 escape
    // fractions and the mix), past its range.
    std::vector<unsigned char> skew = good;
    const double two = 2.0;
    std::memcpy(skew.data() + 4 + 3 * 4 + 15 * 8 + (32 + 33 + 3 + 1) * 8, &two, 8);
    reseal(skew);
    expect_refused(skew, "a longitudinal skew = 2");
    // A cdf value an ulp above 1 before the last edge (a running sum's rounding, as a build
    // of the tables once wrote) loads, brought to 1; a thousandth above is refused.
    const std::size_t cdf_31 = 4 + 3 * 4 + 15 * 8 + (32 + 31) * 8;
    std::vector<unsigned char> ulp = good;
    const double above = std::nextafter(1.0, 2.0);
    std::memcpy(ulp.data() + cdf_31, &above, 8);
    reseal(ulp);
    const std::string ulp_path = temp_path("hairscatter_fur_ulp.hsft");
    write_bytes(ulp_path, ulp);
    EXPECT_NO_THROW(hs::FurMaterial<double>::load(medulla_params<double>(), ulp_path));
    std::vector<unsigned char> past = good;
    const double thousandth = 1.001;
    std::memcpy(past.data() + cdf_31, &thousandth, 8);
    reseal(past);
    expect_refused(past, "a cdf value = 1.001");

    hs::FurParams<double> other = medulla_params<double>();
    other.kappa = 0.3;
    expect_refused(good, "kappa", other);
    other = medulla_params<double>();
    other.sigma_a_medulla.b = 0.5;
    expect_refused(good, "sigma_a_medulla.b", other);

    try {
        hs::FurMaterial<double>::load(medulla_params<double>(), temp_path("hairscatter_no_such_file.hsft"));
        ADD_FAILURE() << "loaded a missing file";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("hairscatter_no_such_file.hsft"), std::string::npos) << e.what();
    }
    hs::FurParams<double> bad = medulla_params<double>();
    bad.kappa = 1;
    EXPECT_THROW(hs::FurMaterial<double>::load(bad, path), std::invalid_argument);
}
