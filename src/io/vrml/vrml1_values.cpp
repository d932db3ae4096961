// VRML 1.0 reader: tokens, located diagnostics and field values.
#include <algorithm>

#include "io/vrml/vrml1_parser.h"

namespace radbake::vrml {

size_t Vrml1MaterialList::count() const {
    return std::max({ambient.size(), diffuse.size(), specular.size(), emissive.size(), shininess.size(),
                     transparency.size(), size_t{1}});
}

Token Vrml1Parser::next() {
    if (replay_ > 0) ++replay_tokens_;
    return lexer_->next();
}

const Token& Vrml1Parser::peek() { return lexer_->peek(); }

SourceLocation Vrml1Parser::loc(const Token& token) const {
    // A re-read DEF's lexer counts from 1:1 at the DEF's node type token.
    const int line = base_line_ + token.line - 1;
    const int column = token.line == 1 ? base_column_ + token.column - 1 : token.column;
    return {path_, line, column};
}

bool Vrml1Parser::fail(const Token& token, const std::string& message) {
    if (!failed_) diagnostics_.error(loc(token), message);
    failed_ = true;
    return false;
}

void Vrml1Parser::warn(const Token& token, const std::string& message) {
    if (replay_ == 0) diagnostics_.warning(loc(token), message);
}

void Vrml1Parser::warnOnce(const std::string& key, const Token& token, const std::string& message) {
    if (replay_ == 0 && warned_.insert(key).second) diagnostics_.warning(loc(token), message);
}

std::string Vrml1Parser::describe(const Token& token) {
    switch (token.kind) {
        case TokenKind::End: return "end of file";
        case TokenKind::String: return "a string";
        case TokenKind::Invalid: return "unexpected character '" + std::string(token.text.substr(0, 1)) + "'";
        default: return "'" + std::string(token.text.substr(0, 40)) + "'";
    }
}

bool Vrml1Parser::readFloat(const Token& field, float& value) {
    const Token t = next();
    if (Lexer::toFloat(t, value)) return true;
    return fail(t, "field '" + std::string(field.text) + "': expected a number, found " + describe(t));
}

bool Vrml1Parser::readInt(const Token& field, int32_t& value) {
    const Token t = next();
    if (Lexer::toInt32(t, value)) return true;
    return fail(t, "field '" + std::string(field.text) + "': expected an integer, found " + describe(t));
}

bool Vrml1Parser::readBool(const Token& field, bool& value) {
    const Token t = next();
    // Inventor also writes SFBool as 0 / 1.
    if (t.text == "TRUE" || t.text == "1") value = true;
    else if (t.text == "FALSE" || t.text == "0") value = false;
    else return fail(t, "field '" + std::string(field.text) + "': expected TRUE or FALSE, found " + describe(t));
    return true;
}

bool Vrml1Parser::readVec2(const Token& field, Vec2& value) {
    return readFloat(field, value.x) && readFloat(field, value.y);
}

bool Vrml1Parser::readVec3(const Token& field, Vec3& value) {
    return readFloat(field, value.x) && readFloat(field, value.y) && readFloat(field, value.z);
}

bool Vrml1Parser::readRotation(const Token& field, DVec3& axis, double& angle) {
    Vec3 a;
    float radians = 0.0f;
    if (!readVec3(field, a) || !readFloat(field, radians)) return false;
    axis = DVec3(a);
    angle = radians;
    return true;
}

bool Vrml1Parser::readMatrix(const Token& field, DMat4& value) {
    // Inventor matrices multiply row vectors (p' = p M), so reading the 16 numbers column by
    // column into GLM's column-major matrix gives the same map for column vectors.
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) {
            float v = 0.0f;
            if (!readFloat(field, v)) return false;
            value[c][r] = v;
        }
    return true;
}

bool Vrml1Parser::readWord(const Token& field, std::string& value) {
    const Token t = next();
    if (t.kind != TokenKind::Word)
        return fail(t, "field '" + std::string(field.text) + "': expected a keyword, found " + describe(t));
    value = std::string(t.text);
    return true;
}

bool Vrml1Parser::readString(const Token& field, std::string& value) {
    const Token t = next();
    // Inventor accepts an unquoted word as a string.
    if (t.kind == TokenKind::String) value = Lexer::decodeString(t);
    else if (t.kind == TokenKind::Word || t.kind == TokenKind::Number) value = std::string(t.text);
    else return fail(t, "field '" + std::string(field.text) + "': expected a string, found " + describe(t));
    return true;
}

bool Vrml1Parser::readBitMask(const Token& field, std::vector<std::string>& names) {
    // SIDES, or (SIDES | TOP): the lexer keeps '(' '|' ')' inside words, so gather words up to
    // the closing parenthesis and split them on '|'.
    names.clear();
    Token t = next();
    if (t.kind != TokenKind::Word)
        return fail(t, "field '" + std::string(field.text) + "': expected a bit mask, found " + describe(t));
    std::string text(t.text);
    if (text.starts_with("(")) {
        for (int guard = 0; !text.ends_with(")"); ++guard) {
            t = next();
            if (t.kind != TokenKind::Word || guard > 64)
                return fail(t, "field '" + std::string(field.text) + "': missing ')' in bit mask");
            text += std::string(t.text);
        }
    }
    std::string current;
    for (char c : text) {
        if (c == '(' || c == ')' || c == ' ') continue;
        if (c == '|') {
            if (!current.empty()) names.push_back(current);
            current.clear();
        } else {
            current.push_back(c);
        }
    }
    if (!current.empty()) names.push_back(current);
    return true;
}

namespace {
// Reads "[ a, b, ... ]" or one bare value, calling read_one for each element.
template <typename ReadOne>
bool readList(Lexer& lexer, ReadOne read_one, bool& ok_bracket_end) {
    ok_bracket_end = true;
    if (lexer.peek().kind != TokenKind::OpenBracket) return read_one();
    lexer.next();
    for (;;) {
        const Token& t = lexer.peek();
        if (t.kind == TokenKind::CloseBracket) {
            lexer.next();
            return true;
        }
        if (t.kind == TokenKind::End || t.kind == TokenKind::CloseBrace || t.kind == TokenKind::OpenBrace) {
            ok_bracket_end = false;
            return false;
        }
        if (!read_one()) return false;
    }
}
}  // namespace

bool Vrml1Parser::readFloats(const Token& field, std::vector<float>& values) {
    values.clear();
    bool bracket_ok = true;
    const bool ok = readList(
        *lexer_,
        [&] {
            float v = 0.0f;
            if (!readFloat(field, v)) return false;
            values.push_back(v);
            return true;
        },
        bracket_ok);
    if (!bracket_ok) return fail(peek(), "field '" + std::string(field.text) + "': missing ']'");
    return ok;
}

bool Vrml1Parser::readInts(const Token& field, std::vector<int32_t>& values) {
    values.clear();
    bool bracket_ok = true;
    const bool ok = readList(
        *lexer_,
        [&] {
            int32_t v = 0;
            if (!readInt(field, v)) return false;
            values.push_back(v);
            return true;
        },
        bracket_ok);
    if (!bracket_ok) return fail(peek(), "field '" + std::string(field.text) + "': missing ']'");
    return ok;
}

bool Vrml1Parser::readVec3s(const Token& field, std::vector<Vec3>& values) {
    values.clear();
    bool bracket_ok = true;
    const bool ok = readList(
        *lexer_,
        [&] {
            Vec3 v;
            if (!readVec3(field, v)) return false;
            values.push_back(v);
            return true;
        },
        bracket_ok);
    if (!bracket_ok) return fail(peek(), "field '" + std::string(field.text) + "': missing ']'");
    return ok;
}

bool Vrml1Parser::skipValue(const Token& field) {
    // Without a declared type, a value is: a bracketed list, a run of numbers, one string,
    // or one keyword (an enum, a bool, or a parenthesised bit mask).
    const Token& first = peek();
    if (first.kind == TokenKind::CloseBrace || first.kind == TokenKind::CloseBracket || first.kind == TokenKind::End)
        return fail(field, "'" + std::string(field.text) + "' has no value (a field without one, or a node without '{')");
    if (first.kind == TokenKind::OpenBracket) {
        const Token open = next();
        for (;;) {
            const Token t = next();
            if (t.kind == TokenKind::CloseBracket) return true;
            if (t.kind == TokenKind::End || t.kind == TokenKind::OpenBrace || t.kind == TokenKind::CloseBrace ||
                t.kind == TokenKind::OpenBracket)
                return fail(open, "field '" + std::string(field.text) + "': '[' without a matching ']'");
        }
    }
    if (first.kind == TokenKind::Number) {
        while (peek().kind == TokenKind::Number) next();
        return true;
    }
    if (first.kind == TokenKind::String) {
        next();
        return true;
    }
    if (first.kind == TokenKind::Word) {
        std::vector<std::string> ignored;
        return readBitMask(field, ignored);
    }
    const Token t = next();
    return fail(t, "field '" + std::string(field.text) + "': expected a value, found " + describe(t));
}

bool Vrml1Parser::skipBody(const Token& type) {
    int depth = 1;
    for (;;) {
        const Token t = next();
        switch (t.kind) {
            case TokenKind::OpenBrace:
            case TokenKind::OpenBracket: ++depth; break;
            case TokenKind::CloseBrace:
            case TokenKind::CloseBracket:
                if (--depth == 0) return true;
                break;
            case TokenKind::End:
                return fail(type, "node '" + std::string(type.text) + "' has no closing '}'");
            default: break;
        }
    }
}

bool Vrml1Parser::unknownField(const Token& field, std::string_view node) {
    if (declared_.count(std::string(field.text))) return skipValue(field);
    const std::string message = "unknown field '" + std::string(field.text) + "' in " + std::string(node);
    if (options_.strict) return fail(field, message);
    // Exporters repeat their private fields on every node (RenderPark's rooms: hundreds of
    // Materials): the first one is reported, the rest counted in one note at the end.
    if (replay_ == 0) {
        auto [it, first] = repeated_.try_emplace(message, loc(field), 0);
        if (first) diagnostics_.warning(loc(field), message + " ignored");
        else ++it->second.second;
    }
    return skipValue(field);
}

}  // namespace radbake::vrml
