#pragma once
// Plain records in a byte string, for radbake's own binary files (a saved solution, a read-out
// shard's part): trivially copyable values and arrays of them (a 64-bit count, then the
// records), read back with every length checked against what is left.
#include <cstdint>
#include <cstring>
#include <deque>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

namespace radbake {

struct Writer {
    std::string bytes;
    template <class T>
    void value(const T& v) {
        static_assert(std::is_trivially_copyable_v<T>);
        bytes.append(reinterpret_cast<const char*>(&v), sizeof v);
    }
    template <class T>
    void array(const std::vector<T>& v) {
        static_assert(std::is_trivially_copyable_v<T>);
        value(static_cast<uint64_t>(v.size()));
        bytes.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
    }
};

// Writer's bytes as views of the memory that holds the records (a value's own bytes; an array's
// size, kept here, then its elements), for writing a large record set without a copy. The records
// must outlive the views.
struct PieceWriter {
    std::deque<uint64_t> sizes;  // deque: the views of earlier sizes stay valid
    std::vector<std::string_view> pieces;
    template <class T>
    void value(const T& v) {
        static_assert(std::is_trivially_copyable_v<T>);
        pieces.emplace_back(reinterpret_cast<const char*>(&v), sizeof v);
    }
    template <class T>
    void array(const std::vector<T>& v) {
        static_assert(std::is_trivially_copyable_v<T>);
        sizes.push_back(static_cast<uint64_t>(v.size()));
        value(sizes.back());
        pieces.emplace_back(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
    }
};

// Reads what Writer wrote; `ok` turns false (and stays) at the first record that does not fit.
struct Reader {
    const std::string& bytes;
    size_t at = 0;
    bool ok = true;
    template <class T>
    void value(T& v) {
        if (!ok || bytes.size() - at < sizeof v) {
            ok = false;
            return;
        }
        std::memcpy(&v, bytes.data() + at, sizeof v);
        at += sizeof v;
    }
    template <class T>
    void array(std::vector<T>& v) {
        uint64_t n = 0;
        value(n);
        if (!ok || n > (bytes.size() - at) / sizeof(T)) {
            ok = false;
            return;
        }
        v.resize(n);
        std::memcpy(v.data(), bytes.data() + at, n * sizeof(T));
        at += n * sizeof(T);
    }
};

}  // namespace radbake
