#pragma once
// Test support: a small strict JSON reader, so tests can parse back what radbake writes
// (glTF JSON chunks, stats.json) without a JSON dependency. Throws std::runtime_error on
// malformed input, which doctest reports as a failed test.
#include <cstdlib>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace minijson {

struct Value {
    enum class Type { Null, Bool, Number, String, Array, Object } type = Type::Null;
    bool boolean = false;
    double number = 0.0;
    std::string string;
    std::vector<Value> array;
    std::map<std::string, Value> object;

    const Value& operator[](const std::string& key) const {
        auto it = object.find(key);
        if (type != Type::Object || it == object.end()) throw std::runtime_error("missing key " + key);
        return it->second;
    }
    const Value& operator[](size_t index) const {
        if (type != Type::Array || index >= array.size()) throw std::runtime_error("bad index");
        return array[index];
    }
    bool has(const std::string& key) const { return type == Type::Object && object.count(key) > 0; }
    size_t size() const { return type == Type::Array ? array.size() : object.size(); }
    double num() const {
        if (type != Type::Number) throw std::runtime_error("not a number");
        return number;
    }
    size_t integer() const { return static_cast<size_t>(num()); }
    const std::string& str() const {
        if (type != Type::String) throw std::runtime_error("not a string");
        return string;
    }
};

class Parser {
public:
    explicit Parser(std::string_view text) : text_(text) {}
    Value parseDocument() {
        Value v = parseValue();
        skipSpace();
        if (pos_ != text_.size()) fail("trailing characters");
        return v;
    }

private:
    [[noreturn]] void fail(const std::string& what) {
        throw std::runtime_error("json: " + what + " at offset " + std::to_string(pos_));
    }
    void skipSpace() {
        while (pos_ < text_.size() && (text_[pos_] == ' ' || text_[pos_] == '\n' || text_[pos_] == '\r' || text_[pos_] == '\t'))
            ++pos_;
    }
    bool consume(char c) {
        skipSpace();
        if (pos_ < text_.size() && text_[pos_] == c) {
            ++pos_;
            return true;
        }
        return false;
    }
    void expect(char c) {
        if (!consume(c)) fail(std::string("expected '") + c + "'");
    }
    bool literal(std::string_view word) {
        if (text_.substr(pos_, word.size()) != word) return false;
        pos_ += word.size();
        return true;
    }
    std::string parseString() {
        expect('"');
        std::string out;
        while (pos_ < text_.size() && text_[pos_] != '"') {
            char c = text_[pos_++];
            if (static_cast<unsigned char>(c) < 0x20) fail("control character in string");
            if (c == '\\') {
                if (pos_ >= text_.size()) fail("bad escape");
                char e = text_[pos_++];
                switch (e) {
                    case 'n': out += '\n'; break;
                    case 't': out += '\t'; break;
                    case 'r': out += '\r'; break;
                    case 'b': out += '\b'; break;
                    case 'f': out += '\f'; break;
                    case 'u': {
                        if (pos_ + 4 > text_.size()) fail("bad \\u escape");
                        const long code = std::strtol(std::string(text_.substr(pos_, 4)).c_str(), nullptr, 16);
                        pos_ += 4;
                        if (code < 0x80) out += static_cast<char>(code);
                        else out += '?';
                        break;
                    }
                    case '"': case '\\': case '/': out += e; break;
                    default: fail("bad escape");
                }
            } else {
                out += c;
            }
        }
        if (pos_ >= text_.size()) fail("unterminated string");
        ++pos_;
        return out;
    }
    Value parseValue() {
        skipSpace();
        if (pos_ >= text_.size()) fail("unexpected end");
        Value v;
        const char c = text_[pos_];
        if (c == '{') {
            ++pos_;
            v.type = Value::Type::Object;
            if (consume('}')) return v;
            do {
                skipSpace();
                std::string key = parseString();
                expect(':');
                if (v.object.count(key)) fail("duplicate key " + key);
                v.object[key] = parseValue();
            } while (consume(','));
            expect('}');
        } else if (c == '[') {
            ++pos_;
            v.type = Value::Type::Array;
            if (consume(']')) return v;
            do v.array.push_back(parseValue());
            while (consume(','));
            expect(']');
        } else if (c == '"') {
            v.type = Value::Type::String;
            v.string = parseString();
        } else if (literal("true")) {
            v.type = Value::Type::Bool;
            v.boolean = true;
        } else if (literal("false")) {
            v.type = Value::Type::Bool;
        } else if (literal("null")) {
        } else {
            const std::string rest(text_.substr(pos_, 64));
            char* end = nullptr;
            v.number = std::strtod(rest.c_str(), &end);
            if (end == rest.c_str()) fail("bad value");
            v.type = Value::Type::Number;
            pos_ += static_cast<size_t>(end - rest.c_str());
        }
        return v;
    }
    std::string_view text_;
    size_t pos_ = 0;
};

inline Value parse(std::string_view text) { return Parser(text).parseDocument(); }

}  // namespace minijson
