#pragma once
// Tokenizer shared by the VRML97 and VRML 1.0 readers. Whitespace, commas and `#` comments
// (to the end of the line, whatever bytes they hold) separate tokens; CR, LF and CRLF all end
// a line. Tokens are views into the text, which must outlive the lexer.
#include <cstdint>
#include <string>
#include <string_view>

#include "core/diagnostics.h"

namespace radbake::vrml {

enum class TokenKind {
    End,           // end of text
    Word,          // identifier or keyword: DEF, USE, TRUE, node and field names, ...
    Number,        // integer (decimal or 0x hex) or float, with optional sign and exponent
    String,        // "..." ; text holds the raw contents between the quotes, escapes undone by decodeString
    OpenBrace,     // {
    CloseBrace,    // }
    OpenBracket,   // [
    CloseBracket,  // ]
    Invalid,       // a byte that starts no token, or an unterminated string
};

struct Token {
    TokenKind kind = TokenKind::End;
    std::string_view text;
    int line = 1;
    int column = 1;
};

class Lexer {
public:
    Lexer(std::string_view text, std::string file_name);

    Token next();               // consumes
    const Token& peek();        // looks ahead one token without consuming

    SourceLocation location(const Token& token) const { return {file_name_, token.line, token.column}; }
    const std::string& fileName() const { return file_name_; }

    // Conversions; false when the token is not a well-formed number of that kind.
    static bool toDouble(const Token& token, double& value);
    static bool toFloat(const Token& token, float& value);
    static bool toInt32(const Token& token, int32_t& value);  // decimal or 0x hex
    static std::string decodeString(const Token& token);     // undoes \" and \\ escapes

private:
    Token scan();
    std::string_view text_;
    std::string file_name_;
    size_t pos_ = 0;
    int line_ = 1;
    size_t line_start_ = 0;
    Token lookahead_;
    bool has_lookahead_ = false;
};

}  // namespace radbake::vrml
