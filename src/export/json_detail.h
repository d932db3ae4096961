#pragma once
// Private to src/export: the stage's one include of nlohmann/json (no public header has it),
// and the one way the stage turns JSON into bytes, so that every file it writes is laid out
// the same way run after run.
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace radbake::json_detail {

// Keys in insertion order: a file's layout is fixed by the code that builds it, not sorted.
using Json = nlohmann::ordered_json;

// glTF's numbers are floats (every value the glb holds is a float): with float as the number
// type, a value prints as the shortest text that reads back as the same float (0.1f is
// "0.1", not "0.10000000149011612").
using GltfJson = nlohmann::basic_json<nlohmann::ordered_map, std::vector, std::string, bool, std::int64_t,
                                      std::uint64_t, float>;

// `indent` < 0: one line, no spaces. Invalid UTF-8 in a string (a file name in another
// encoding) becomes U+FFFD instead of an exception; NaN and infinities are written as null.
template <typename JsonType>
std::string dump(const JsonType& value, int indent) {
    return value.dump(indent, ' ', false, JsonType::error_handler_t::replace);
}

}  // namespace radbake::json_detail
