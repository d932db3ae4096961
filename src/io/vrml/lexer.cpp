#include "io/vrml/lexer.h"

#include <array>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <limits>

namespace radbake::vrml {
namespace {

enum CharClass : uint8_t {
    kInvalid = 0,
    kSpace,       // blanks, tabs, commas (VRML treats commas as whitespace)
    kNewline,     // CR or LF
    kComment,     // #
    kQuote,       // "
    kBrace,       // { } [ ]
    kNumberStart, // digits, + - .
    kWordStart,   // letters, _, and every byte >= 0x80 (UTF-8 names)
};

// Bytes that may continue a word. VRML forbids '.' inside names, but accepting it keeps
// `ROUTE a.b TO c.d` as two tokens the parser splits itself.
constexpr bool isWordRest(unsigned char c) {
    if (c <= 0x20 || c == 0x7f) return false;
    switch (c) {
        case '"': case '#': case '\'': case ',': case '[': case '\\': case ']': case '{': case '}':
            return false;
        default: return true;
    }
}

constexpr std::array<uint8_t, 256> makeClassTable() {
    std::array<uint8_t, 256> table{};
    for (int c = 0; c < 256; ++c) {
        uint8_t k = kInvalid;
        if (c == ' ' || c == '\t' || c == ',' || c == '\f' || c == '\v') k = kSpace;
        else if (c == '\n' || c == '\r') k = kNewline;
        else if (c == '#') k = kComment;
        else if (c == '"') k = kQuote;
        else if (c == '{' || c == '}' || c == '[' || c == ']') k = kBrace;
        else if ((c >= '0' && c <= '9') || c == '+' || c == '-' || c == '.') k = kNumberStart;
        else if (isWordRest(static_cast<unsigned char>(c))) k = kWordStart;
        table[static_cast<size_t>(c)] = k;
    }
    return table;
}

constexpr std::array<uint8_t, 256> kClass = makeClassTable();

constexpr std::array<bool, 256> makeRestTable() {
    std::array<bool, 256> table{};
    for (int c = 0; c < 256; ++c) table[static_cast<size_t>(c)] = isWordRest(static_cast<unsigned char>(c));
    return table;
}

constexpr std::array<bool, 256> kWordRest = makeRestTable();

bool isDigit(char c) { return c >= '0' && c <= '9'; }

bool isHexLiteral(std::string_view s) {
    if (!s.empty() && (s[0] == '+' || s[0] == '-')) s.remove_prefix(1);
    return s.size() > 2 && s[0] == '0' && (s[1] == 'x' || s[1] == 'X');
}

// Parses [+-]0xHHHH as a 32-bit pattern (SFImage pixels use the full unsigned range).
bool parseHex(std::string_view s, int64_t& value) {
    bool negative = false;
    if (s[0] == '+' || s[0] == '-') {
        negative = s[0] == '-';
        s.remove_prefix(1);
    }
    s.remove_prefix(2);
    uint64_t v = 0;
    auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v, 16);
    if (ec != std::errc() || end != s.data() + s.size() || v > 0xffffffffull) return false;
    value = negative ? -static_cast<int64_t>(v) : static_cast<int64_t>(v);
    return true;
}

// Fast path for the common "[-+]ddd[.ddd]" form: the digits as an integer m < 2^53 and a
// power of ten p <= 22 are both exact doubles, so m / 10^p is correctly rounded, the same
// value from_chars gives. False (not handled) for anything else.
bool fastDecimal(std::string_view s, double& value) {
    static constexpr double kPow10[] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,  1e8,  1e9,  1e10, 1e11,
                                        1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};
    size_t i = 0;
    bool negative = false;
    if (i < s.size() && (s[i] == '-' || s[i] == '+')) negative = s[i++] == '-';
    uint64_t mantissa = 0;
    int digits = 0, fraction = 0;
    bool dot = false, any_digit = false;
    for (; i < s.size(); ++i) {
        const char c = s[i];
        if (c >= '0' && c <= '9') {
            any_digit = true;
            mantissa = mantissa * 10 + uint64_t(c - '0');
            if (mantissa != 0 || dot) ++digits;
            if (dot) ++fraction;
            if (digits > 15 || fraction > 22) return false;
        } else if (c == '.' && !dot) {
            dot = true;
        } else {
            return false;
        }
    }
    if (!any_digit) return false;
    const double v = double(mantissa) / kPow10[fraction];
    value = negative ? -v : v;
    return true;
}

}  // namespace

Lexer::Lexer(std::string_view text, std::string file_name) : text_(text), file_name_(std::move(file_name)) {
    // A UTF-8 byte order mark is not part of the text.
    if (text_.starts_with("\xEF\xBB\xBF")) pos_ = line_start_ = 3;
}

Token Lexer::next() {
    if (has_lookahead_) {
        has_lookahead_ = false;
        return lookahead_;
    }
    return scan();
}

const Token& Lexer::peek() {
    if (!has_lookahead_) {
        lookahead_ = scan();
        has_lookahead_ = true;
    }
    return lookahead_;
}

Token Lexer::scan() {
    const size_t n = text_.size();
    const char* s = text_.data();
    for (;;) {
        if (pos_ >= n) {
            Token end{TokenKind::End, text_.substr(n, 0), line_, static_cast<int>(pos_ - line_start_) + 1};
            return end;
        }
        const unsigned char c = static_cast<unsigned char>(s[pos_]);
        const uint8_t k = kClass[c];
        if (k == kSpace) {
            ++pos_;
        } else if (k == kNewline) {
            // CRLF counts as one line end.
            ++pos_;
            if (c == '\r' && pos_ < n && s[pos_] == '\n') ++pos_;
            ++line_;
            line_start_ = pos_;
        } else if (k == kComment) {
            while (pos_ < n && s[pos_] != '\n' && s[pos_] != '\r') ++pos_;
        } else {
            break;
        }
    }

    const unsigned char c = static_cast<unsigned char>(s[pos_]);
    Token token;
    token.line = line_;
    token.column = static_cast<int>(pos_ - line_start_) + 1;
    const size_t start = pos_;
    switch (kClass[c]) {
        case kBrace:
            token.kind = c == '{'   ? TokenKind::OpenBrace
                         : c == '}' ? TokenKind::CloseBrace
                         : c == '[' ? TokenKind::OpenBracket
                                    : TokenKind::CloseBracket;
            ++pos_;
            break;
        case kQuote: {
            ++pos_;
            bool closed = false;
            while (pos_ < n) {
                const char d = s[pos_];
                if (d == '\\' && pos_ + 1 < n) {
                    pos_ += 2;
                    if (s[pos_ - 1] == '\n' || s[pos_ - 1] == '\r') {
                        // an escaped line end still ends a line
                        if (s[pos_ - 1] == '\r' && pos_ < n && s[pos_] == '\n') ++pos_;
                        ++line_;
                        line_start_ = pos_;
                    }
                    continue;
                }
                if (d == '"') {
                    closed = true;
                    break;
                }
                ++pos_;
                if (d == '\n' || d == '\r') {
                    if (d == '\r' && pos_ < n && s[pos_] == '\n') ++pos_;
                    ++line_;
                    line_start_ = pos_;
                }
            }
            if (closed) {
                token.kind = TokenKind::String;
                token.text = text_.substr(start + 1, pos_ - start - 1);
                ++pos_;
            } else {
                token.kind = TokenKind::Invalid;
                token.text = text_.substr(start, pos_ - start);
            }
            return token;
        }
        case kNumberStart: {
            // Scan the longest run of bytes that may continue a token; the conversions decide
            // whether it is a well-formed number, so "1.5f" is one bad number, not two tokens.
            ++pos_;
            while (pos_ < n && kWordRest[static_cast<unsigned char>(s[pos_])]) {
                // A sign only continues a number right after an exponent letter; "1-2" in a
                // squeezed list is two numbers.
                const char d = s[pos_];
                if ((d == '+' || d == '-') && !(s[pos_ - 1] == 'e' || s[pos_ - 1] == 'E')) break;
                ++pos_;
            }
            token.kind = TokenKind::Number;
            break;
        }
        case kWordStart:
            ++pos_;
            while (pos_ < n && kWordRest[static_cast<unsigned char>(s[pos_])]) ++pos_;
            token.kind = TokenKind::Word;
            break;
        default:
            token.kind = TokenKind::Invalid;
            ++pos_;
            break;
    }
    token.text = text_.substr(start, pos_ - start);
    return token;
}

bool Lexer::toDouble(const Token& token, double& value) {
    if (token.kind != TokenKind::Number) return false;
    std::string_view s = token.text;
    if (fastDecimal(s, value)) return true;
    if (isHexLiteral(s)) {
        int64_t v = 0;
        if (!parseHex(s, v)) return false;
        value = static_cast<double>(v);
        return true;
    }
    bool negative = false;
    if (!s.empty() && (s[0] == '+' || s[0] == '-')) {
        negative = s[0] == '-';
        s.remove_prefix(1);
    }
    // from_chars would accept "inf" and "nan"; VRML numbers start with a digit or a dot.
    if (s.empty() || !(isDigit(s[0]) || (s[0] == '.' && s.size() > 1 && isDigit(s[1])))) return false;
    double v = 0.0;
    auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v, std::chars_format::general);
    if (end != s.data() + s.size()) return false;
    if (ec == std::errc::result_out_of_range) {
        // Underflow reads as (nearly) zero, overflow as infinity, which validation reports.
        std::string copy(s);
        errno = 0;
        v = std::strtod(copy.c_str(), nullptr);
    } else if (ec != std::errc()) {
        return false;
    }
    value = negative ? -v : v;
    return true;
}

bool Lexer::toFloat(const Token& token, float& value) {
    double v = 0.0;
    if (!toDouble(token, v)) return false;
    value = static_cast<float>(v);
    return true;
}

bool Lexer::toInt32(const Token& token, int32_t& value) {
    if (token.kind != TokenKind::Number) return false;
    std::string_view s = token.text;
    {
        // Fast path: up to 9 decimal digits always fit in an int32.
        size_t i = 0;
        const bool negative = !s.empty() && s[0] == '-';
        if (!s.empty() && (s[0] == '-' || s[0] == '+')) i = 1;
        if (s.size() > i && s.size() - i <= 9) {
            int32_t v = 0;
            size_t k = i;
            for (; k < s.size() && s[k] >= '0' && s[k] <= '9'; ++k) v = v * 10 + (s[k] - '0');
            if (k == s.size()) {
                value = negative ? -v : v;
                return true;
            }
        }
    }
    if (isHexLiteral(s)) {
        int64_t v = 0;
        if (!parseHex(s, v)) return false;
        value = static_cast<int32_t>(static_cast<uint32_t>(v));
        return true;
    }
    std::string_view digits = s;
    if (!digits.empty() && digits[0] == '+') digits.remove_prefix(1);
    int64_t v = 0;
    auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), v, 10);
    if (ec == std::errc() && end == digits.data() + digits.size()) {
        if (v < std::numeric_limits<int32_t>::min() || v > std::numeric_limits<int32_t>::max()) return false;
        value = static_cast<int32_t>(v);
        return true;
    }
    // Some exporters write integers as "3.0"; accept exact integral values.
    double d = 0.0;
    if (!toDouble(token, d) || d != std::floor(d) || d < std::numeric_limits<int32_t>::min() ||
        d > std::numeric_limits<int32_t>::max())
        return false;
    value = static_cast<int32_t>(d);
    return true;
}

std::string Lexer::decodeString(const Token& token) {
    std::string out;
    out.reserve(token.text.size());
    for (size_t i = 0; i < token.text.size(); ++i) {
        char c = token.text[i];
        if (c == '\\' && i + 1 < token.text.size()) c = token.text[++i];
        out.push_back(c);
    }
    return out;
}

}  // namespace radbake::vrml
