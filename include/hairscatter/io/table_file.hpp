// hairscatter — the byte-level pieces of the library's small binary table files (the dual-
// scattering tables, the fur's medulla tables): values appended to and read from a buffer
// in the machine's byte order, and the FNV-1a checksum that closes each file. Host only.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "../config.hpp"

namespace hairscatter {
namespace detail {

// FNV-1a, 64 bits (Fowler, Noll & Vo): a corrupt byte changes it.
inline std::uint64_t fnv1a(const unsigned char* p, std::size_t n) {
    std::uint64_t h = 1469598103934665603ull;
    for (std::size_t i = 0; i < n; ++i) h = (h ^ p[i]) * 1099511628211ull;
    return h;
}

inline void put_bytes(std::vector<unsigned char>& b, const void* p, std::size_t n) {
    const auto* c = static_cast<const unsigned char*>(p);
    b.insert(b.end(), c, c + n);
}

// The U at b[at] (the caller has checked that it lies inside b); at moves past it.
template <typename U> U get_bytes(const std::vector<unsigned char>& b, std::size_t& at) {
    U v;
    std::memcpy(&v, b.data() + at, sizeof(U));
    at += sizeof(U);
    return v;
}

// buf followed by its FNV-1a checksum, written to path; std::runtime_error naming what the
// file holds and the path when it cannot be written.
inline void write_table_file(const std::string& path, std::vector<unsigned char> buf, const std::string& what) {
    const std::uint64_t sum = fnv1a(buf.data(), buf.size());
    put_bytes(buf, &sum, 8);
    std::ofstream f(path, std::ios::binary);
    if (!f) HAIRSCATTER_THROW(std::runtime_error("hairscatter: cannot write " + what + " to '" + path + "'"));
    f.write(reinterpret_cast<const char*>(buf.data()), std::streamsize(buf.size()));
    if (!f) HAIRSCATTER_THROW(std::runtime_error("hairscatter: failed writing " + what + " to '" + path + "'"));
}

}  // namespace detail
}  // namespace hairscatter
