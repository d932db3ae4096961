#include "io/vrml/vrml97_parser.h"

#include <optional>

#include <algorithm>
#include <filesystem>
#include <string>
#include <unordered_set>

namespace radbake::vrml {
namespace {

// Thrown inside the parser for a fatal syntax error; caught in Vrml97Parser::parse.
struct ParseError {
    SourceLocation location;
    std::string message;
};

std::string describe(const Token& t) {
    switch (t.kind) {
        case TokenKind::End: return "end of file";
        case TokenKind::String: return "a string";
        case TokenKind::OpenBrace: return "'{'";
        case TokenKind::CloseBrace: return "'}'";
        case TokenKind::OpenBracket: return "'['";
        case TokenKind::CloseBracket: return "']'";
        case TokenKind::Invalid:
            if (!t.text.empty() && t.text[0] == '"') return "an unterminated string";
            return "an unexpected character";
        default: {
            std::string text(t.text.substr(0, 40));
            return "'" + text + "'";
        }
    }
}

bool isWord(const Token& t, std::string_view word) { return t.kind == TokenKind::Word && t.text == word; }

// X3D classic encoding (.x3dv) is VRML97 syntax plus these statements, which say nothing
// about geometry or light; a node of the same name would be followed by '{'.
bool isX3dStatement(std::string_view word) {
    return word == "PROFILE" || word == "COMPONENT" || word == "META" || word == "UNIT" || word == "IMPORT" ||
           word == "EXPORT";
}

Token expectToken(Lexer& lexer, TokenKind kind, const char* what) {
    Token t = lexer.next();
    if (t.kind != kind) throw ParseError{lexer.location(t), std::string("expected ") + what + ", found " + describe(t)};
    return t;
}

// PROFILE name | COMPONENT name:level | META "key" "value" | UNIT category name factor |
// IMPORT inline.exported [AS name] | EXPORT name [AS name]: skipped, one warning per kind
// (`warned` holds the kinds already reported in this file).
void skipX3dStatement(Lexer& lexer, Diagnostics& diagnostics, std::unordered_set<std::string>& warned) {
    const Token keyword = lexer.next();
    const std::string kind(keyword.text);
    if (kind == "PROFILE") {
        expectToken(lexer, TokenKind::Word, "a profile name after PROFILE");
    } else if (kind == "COMPONENT") {
        Token name = expectToken(lexer, TokenKind::Word, "a component name after COMPONENT");
        // name:level, possibly written with spaces around the colon.
        if (name.text.find(':') == std::string_view::npos && lexer.peek().kind == TokenKind::Word &&
            lexer.peek().text.starts_with(':'))
            name = lexer.next();
        if (name.text.ends_with(':')) expectToken(lexer, TokenKind::Number, "a component level after ':'");
    } else if (kind == "META") {
        expectToken(lexer, TokenKind::String, "a key string after META");
        expectToken(lexer, TokenKind::String, "a value string after the META key");
    } else if (kind == "UNIT") {
        expectToken(lexer, TokenKind::Word, "a unit category after UNIT");
        expectToken(lexer, TokenKind::Word, "a unit name after the UNIT category");
        expectToken(lexer, TokenKind::Number, "a conversion factor after the UNIT name");
    } else {  // IMPORT, EXPORT
        expectToken(lexer, TokenKind::Word,
                    kind == "IMPORT" ? "inlineName.exportedName after IMPORT" : "a node name after EXPORT");
        if (isWord(lexer.peek(), "AS")) {
            lexer.next();
            expectToken(lexer, TokenKind::Word, "a name after AS");
        }
    }
    if (!warned.insert("X3D " + kind).second) return;
    diagnostics.warning(lexer.location(keyword),
                        "X3D " + kind + " statement(s) skipped (X3D classic files are read as VRML97)" +
                            (kind == "UNIT" ? std::string("; lengths are read unscaled: give --unit-scale for a length unit")
                                            : std::string()));
}

bool equalsIgnoreCase(std::string_view a, std::string_view b) {
    return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
               return std::tolower(static_cast<unsigned char>(x)) == std::tolower(static_cast<unsigned char>(y));
           });
}

}  // namespace

Vrml97Limits& vrml97Limits() {
    static Vrml97Limits limits;
    return limits;
}

Vrml97Parser::Vrml97Parser(std::string_view text, std::string path, const VrmlOptions& options,
                           std::vector<std::string>& file_stack, Diagnostics& diagnostics)
    : lexer_(text, path), path_(std::move(path)), options_(options), file_stack_(file_stack),
      diagnostics_(diagnostics) {}

bool Vrml97Parser::parse(std::vector<NodePtr>& roots) {
    try {
        while (lexer_.peek().kind != TokenKind::End) parseStatement(top_, roots, 0);
    } catch (const ParseError& e) {
        diagnostics_.error(e.location, e.message);
        return false;
    }
    return !had_error_;
}

std::shared_ptr<const ProtoDef> Vrml97Parser::findTopLevelProto(std::string_view name) const {
    const auto it = top_.protos.find(std::string(name));
    return it == top_.protos.end() ? nullptr : it->second;
}

void Vrml97Parser::fail(const Token& at, const std::string& message) { throw ParseError{loc(at), message}; }

void Vrml97Parser::unknown(const Token& at, const std::string& message) {
    if (options_.strict) {
        diagnostics_.error(loc(at), message);
        had_error_ = true;
    } else {
        diagnostics_.warning(loc(at), message);
    }
}

Token Vrml97Parser::expect(TokenKind kind, const char* what) {
    Token t = lexer_.next();
    if (t.kind != kind) fail(t, std::string("expected ") + what + ", found " + describe(t));
    return t;
}

std::shared_ptr<ProtoDef> Vrml97Parser::findProto(const Scope& scope, std::string_view name) const {
    for (const Scope* s = &scope; s; s = s->parent) {
        const auto it = s->protos.find(std::string(name));
        if (it != s->protos.end()) return it->second;
    }
    return nullptr;
}

void Vrml97Parser::parseStatement(Scope& scope, std::vector<NodePtr>& out, int depth) {
    const Token& t = lexer_.peek();
    if (t.kind == TokenKind::Word) {
        if (t.text == "PROTO" || t.text == "EXTERNPROTO" || t.text == "ROUTE") {
            const Token keyword = lexer_.next();
            parseBodyExtra(keyword, scope, depth);
            return;
        }
        if (isX3dStatement(t.text)) {
            Lexer ahead = lexer_;  // two tokens of lookahead, only for these rare words
            ahead.next();
            if (ahead.peek().kind != TokenKind::OpenBrace) {
                skipX3dStatement(lexer_, diagnostics_, warned_kinds_);
                return;
            }
        }
    }
    if (NodePtr node = parseNodeStatement(scope, depth)) out.push_back(std::move(node));
}

NodePtr Vrml97Parser::parseNodeStatement(Scope& scope, int depth) {
    Token t = lexer_.next();
    if (t.kind != TokenKind::Word) fail(t, "expected a node, found " + describe(t));
    if (t.text == "NULL") return nullptr;
    if (t.text == "USE") {
        const Token name = expect(TokenKind::Word, "a node name after USE");
        const auto it = scope.defs.find(std::string(name.text));
        if (it == scope.defs.end()) {
            // A USE of a skipped (unknown) node lands here too: skip it rather than fail.
            diagnostics_.warning(loc(name), "USE of undefined node name '" + std::string(name.text) + "' ignored");
            return nullptr;
        }
        return it->second;
    }
    if (t.text == "DEF") {
        const Token name = expect(TokenKind::Word, "a node name after DEF");
        const Token type = expect(TokenKind::Word, "a node type after DEF name");
        NodePtr node = parseNode(type, scope, depth);
        // Registered only now, so the node cannot USE itself; a later DEF of the same name
        // replaces this one for later USEs.
        if (node) {
            node->name = std::string(name.text);
            scope.defs[node->name] = node;
        } else {
            scope.defs.erase(std::string(name.text));
        }
        return node;
    }
    return parseNode(t, scope, depth);
}

NodePtr Vrml97Parser::parseNode(const Token& type, Scope& scope, int depth) {
    if (depth >= vrml97Limits().max_nesting)
        fail(type, "nodes nested deeper than " + std::to_string(vrml97Limits().max_nesting) + " levels");
    if (type.kind != TokenKind::Word || type.text == "DEF" || type.text == "USE" || type.text == "IS")
        fail(type, "expected a node type, found " + describe(type));
    const Token open = lexer_.next();
    if (open.kind != TokenKind::OpenBrace)
        fail(open, "expected '{' after node type '" + std::string(type.text) + "', found " + describe(open));

    auto node = std::make_shared<Node>();
    node->type = std::string(type.text);
    node->location = loc(type);
    if (std::shared_ptr<ProtoDef> proto = findProto(scope, type.text)) {
        // The instance owns its definition: the body may redefine the name (a PROTO inside a
        // node body), which must neither free the definition in use nor rebind the instance.
        node->proto = proto;
        parseProtoInstanceBody(*node, *proto, scope, depth + 1);
    } else {
        const NodeSpec* spec = findNodeSpec(type.text);
        if (!spec || spec->role != NodeRole::Used) {
            if (!spec) {
                unknown(type, "unknown node type '" + node->type + "' skipped");
            } else if (spec->role == NodeRole::Unsupported && warned_kinds_.insert(node->type).second) {
                diagnostics_.warning(loc(type), node->type + " nodes are ignored (lines, points and text carry no area)");
            }
            skipBraces(open);
            return nullptr;
        }
        parseBuiltinBody(*node, *spec, scope, depth + 1);
    }
    if (!node->is_bindings.empty()) node->subtree_has_is = true;
    return node;
}

bool Vrml97Parser::parseBodyExtra(const Token& word, Scope& scope, int depth) {
    if (word.text == "ROUTE") {
        skipRoute(word);
        return true;
    }
    if (word.text == "PROTO") {
        parseProto(word, scope, depth);
        return true;
    }
    if (word.text == "EXTERNPROTO") {
        parseExternProto(scope);
        return true;
    }
    return false;
}

bool Vrml97Parser::parseIs(Node& node, const Token& field_name, Scope& scope) {
    if (!isWord(lexer_.peek(), "IS")) return false;
    const Token is = lexer_.next();
    const Token target = expect(TokenKind::Word, "an interface field name after IS");
    if (!scope.proto) fail(is, "IS outside a PROTO body");
    if (!scope.proto->find(target.text)) {
        unknown(target, "IS refers to '" + std::string(target.text) + "', which PROTO " + scope.proto->name +
                            " does not declare; binding ignored");
        return true;
    }
    node.is_bindings.push_back({std::string(field_name.text), std::string(target.text)});
    return true;
}

// Marks the node when a node below it is bound through IS, so PROTO expansion copies
// exactly the path down to every binding and shares the rest.
static void noteChildren(Node& node, const FieldValue& value) {
    for (const NodePtr& child : value.nodes)
        if (child && child->subtree_has_is) node.subtree_has_is = true;
}

std::optional<Token> Vrml97Parser::nextBodyField(Node& node, Scope& scope, int depth) {
    for (;;) {
        const Token t = lexer_.next();
        if (t.kind == TokenKind::CloseBrace) return std::nullopt;
        if (t.kind == TokenKind::End)
            fail(t, "unexpected end of file inside " + node.type + " (opened at line " + std::to_string(node.location.line) +
                        ", column " + std::to_string(node.location.column) + ")");
        if (t.kind != TokenKind::Word)
            fail(t, "expected a field name or '}' in " + node.type + ", found " + describe(t));
        if (parseBodyExtra(t, scope, depth)) continue;
        if (parseIs(node, t, scope)) continue;  // events bound with IS are accepted and unused
        return t;
    }
}

void Vrml97Parser::parseBuiltinBody(Node& node, const NodeSpec& spec, Scope& scope, int depth) {
    while (const std::optional<Token> field_name = nextBodyField(node, scope, depth)) {
        const Token& t = *field_name;
        const FieldSpec* field = spec.find(t.text);
        if (!field) {
            unknown(t, "unknown field '" + std::string(t.text) + "' in " + node.type + " skipped");
            skipValue();
            continue;
        }
        FieldValue* value = node.field(field->name);
        if (!value) {
            node.fields.push_back({std::string(field->name), {}});
            value = &node.fields.back().value;
        } else {
            *value = {};  // a repeated field: the last one wins
        }
        value->type = field->type;
        parseValue(field->type, *value, t, scope, depth);
        noteChildren(node, *value);
    }
}

void Vrml97Parser::parseProtoInstanceBody(Node& node, const ProtoDef& proto, Scope& scope, int depth) {
    while (const std::optional<Token> field_name = nextBodyField(node, scope, depth)) {
        const Token& t = *field_name;
        const InterfaceField* field = proto.find(t.text);
        if (!field || field->is_event) {
            unknown(t, "unknown field '" + std::string(t.text) + "' in PROTO instance " + node.type + " skipped");
            skipValue();
            continue;
        }
        FieldValue* value = node.field(field->name);
        if (!value) {
            node.fields.push_back({field->name, {}});
            value = &node.fields.back().value;
        } else {
            *value = {};
        }
        value->type = field->type;
        parseValue(field->type, *value, t, scope, depth);
        noteChildren(node, *value);
    }
}

void Vrml97Parser::parseNumbers(FieldType type, FieldValue& value, const Token& field_name) {
    const int n = arity(type);
    const bool floats = isFloatType(type);
    auto readOne = [&](const Token& t) {
        if (floats) {
            float f = 0.0f;
            if (!Lexer::toFloat(t, f)) fail(t, "expected a number for field '" + std::string(field_name.text) + "', found " + describe(t));
            value.floats.push_back(f);
        } else {
            int32_t i = 0;
            if (!Lexer::toInt32(t, i)) fail(t, "expected an integer for field '" + std::string(field_name.text) + "', found " + describe(t));
            value.ints.push_back(i);
        }
    };
    if (isMultiple(type) && lexer_.peek().kind == TokenKind::OpenBracket) {
        const Token open = lexer_.next();
        size_t count = 0;
        for (;;) {
            const Token t = lexer_.next();
            if (t.kind == TokenKind::CloseBracket) break;
            readOne(t);
            ++count;
        }
        if (count % static_cast<size_t>(n) != 0) {
            diagnostics_.warning(loc(open), "field '" + std::string(field_name.text) + "' holds " + std::to_string(count) +
                                                " numbers, not a multiple of " + std::to_string(n) + "; the rest is ignored");
            if (floats) value.floats.resize(value.floats.size() - count % static_cast<size_t>(n));
            else value.ints.resize(value.ints.size() - count % static_cast<size_t>(n));
        }
        return;
    }
    for (int k = 0; k < n; ++k) readOne(lexer_.next());
}

void Vrml97Parser::parseValue(FieldType type, FieldValue& value, const Token& field_name, Scope& scope, int depth) {
    const std::string name(field_name.text);
    switch (type) {
        case FieldType::SFBool:
        case FieldType::MFBool: {
            auto readBool = [&](const Token& t) {
                if (t.kind == TokenKind::Word && equalsIgnoreCase(t.text, "TRUE")) value.ints.push_back(1);
                else if (t.kind == TokenKind::Word && equalsIgnoreCase(t.text, "FALSE")) value.ints.push_back(0);
                else fail(t, "expected TRUE or FALSE for field '" + name + "', found " + describe(t));
            };
            if (type == FieldType::MFBool && lexer_.peek().kind == TokenKind::OpenBracket) {
                lexer_.next();
                for (Token t = lexer_.next(); t.kind != TokenKind::CloseBracket; t = lexer_.next()) readBool(t);
            } else {
                readBool(lexer_.next());
            }
            return;
        }
        case FieldType::SFString:
        case FieldType::MFString: {
            auto readString = [&](const Token& t) {
                if (t.kind != TokenKind::String) fail(t, "expected a string for field '" + name + "', found " + describe(t));
                value.strings.push_back(Lexer::decodeString(t));
            };
            if (type == FieldType::MFString && lexer_.peek().kind == TokenKind::OpenBracket) {
                lexer_.next();
                for (Token t = lexer_.next(); t.kind != TokenKind::CloseBracket; t = lexer_.next()) readString(t);
            } else {
                readString(lexer_.next());
            }
            return;
        }
        case FieldType::SFImage: {
            // width height components, then width*height pixels; read every number that follows.
            for (int k = 0; k < 3; ++k) {
                const Token t = lexer_.next();
                int32_t i = 0;
                if (!Lexer::toInt32(t, i)) fail(t, "expected an integer for field '" + name + "', found " + describe(t));
                value.ints.push_back(i);
            }
            while (lexer_.peek().kind == TokenKind::Number) {
                const Token t = lexer_.next();
                int32_t i = 0;
                if (!Lexer::toInt32(t, i)) fail(t, "expected an integer pixel for field '" + name + "', found " + describe(t));
                value.ints.push_back(i);
            }
            return;
        }
        case FieldType::SFNode:
            value.nodes.push_back(parseNodeStatement(scope, depth));
            return;
        case FieldType::MFNode:
            if (lexer_.peek().kind == TokenKind::OpenBracket) {
                lexer_.next();
                while (lexer_.peek().kind != TokenKind::CloseBracket) {
                    if (lexer_.peek().kind == TokenKind::End) fail(lexer_.peek(), "unexpected end of file in field '" + name + "'");
                    std::vector<NodePtr> nodes;
                    parseStatement(scope, nodes, depth);
                    for (NodePtr& n : nodes) value.nodes.push_back(std::move(n));
                }
                lexer_.next();
            } else if (NodePtr node = parseNodeStatement(scope, depth)) {
                value.nodes.push_back(std::move(node));
            }
            return;
        default:
            parseNumbers(type, value, field_name);
            return;
    }
}

void Vrml97Parser::parseInterface(ProtoDef& proto, bool with_values, Scope& scope, int depth) {
    expect(TokenKind::OpenBracket, "'[' to open the PROTO interface");
    for (;;) {
        const Token kind = lexer_.next();
        if (kind.kind == TokenKind::CloseBracket) return;
        const bool event = isWord(kind, "eventIn") || isWord(kind, "eventOut");
        if (!event && !isWord(kind, "field") && !isWord(kind, "exposedField"))
            fail(kind, "expected field, exposedField, eventIn, eventOut or ']' in PROTO " + proto.name + ", found " +
                           describe(kind));
        const Token type_token = expect(TokenKind::Word, "a field type");
        InterfaceField field;
        if (!parseFieldType(type_token.text, field.type))
            fail(type_token, "unknown field type '" + std::string(type_token.text) + "'");
        const Token name = expect(TokenKind::Word, "a field name");
        field.name = std::string(name.text);
        field.is_event = event;
        field.default_value.type = field.type;
        if (with_values && !event) {
            // Nodes in a default value live in the enclosing scope.
            parseValue(field.type, field.default_value, name, scope, depth);
        }
        proto.interface.push_back(std::move(field));
    }
}

void Vrml97Parser::parseProto(const Token& keyword, Scope& scope, int depth) {
    if (depth >= vrml97Limits().max_nesting) fail(keyword, "PROTOs nested too deeply");
    const Token name = expect(TokenKind::Word, "a PROTO name");
    auto proto = std::make_shared<ProtoDef>();
    proto->name = std::string(name.text);
    proto->location = loc(name);
    parseInterface(*proto, true, scope, depth + 1);
    expect(TokenKind::OpenBrace, "'{' to open the PROTO body");
    Scope body;
    body.parent = &scope;
    body.proto = proto.get();
    while (lexer_.peek().kind != TokenKind::CloseBrace) {
        if (lexer_.peek().kind == TokenKind::End) fail(lexer_.peek(), "unexpected end of file in PROTO " + proto->name);
        parseStatement(body, proto->body, depth + 1);
    }
    lexer_.next();
    if (proto->body.empty()) diagnostics_.warning(loc(name), "PROTO " + proto->name + " has no node in its body");
    scope.protos[proto->name] = proto;
    if (&scope == &top_ && !first_proto_) first_proto_ = proto;
}

void Vrml97Parser::parseExternProto(Scope& scope) {
    const Token name = expect(TokenKind::Word, "an EXTERNPROTO name");
    auto proto = std::make_shared<ProtoDef>();
    proto->name = std::string(name.text);
    proto->location = loc(name);
    parseInterface(*proto, false, scope, 0);
    FieldValue urls;
    urls.type = FieldType::MFString;
    parseValue(FieldType::MFString, urls, name, scope, 0);
    resolveExternProto(*proto, urls.strings, name);
    scope.protos[proto->name] = proto;
}

void Vrml97Parser::resolveExternProto(ProtoDef& proto, const std::vector<std::string>& urls, const Token& at) {
    proto.unresolved = true;
    bool refused = false;
    for (const std::string& url : urls) {
        const size_t hash = url.find('#');
        const std::string file = url.substr(0, hash);
        const std::string wanted = hash == std::string::npos ? std::string() : url.substr(hash + 1);
        std::shared_ptr<const ProtoDef> found;
        if (file.empty()) continue;  // "#Name" names a PROTO of this file, which would be a PROTO
        const std::optional<std::string> resolved = resolveUrl(path_, file);
        if (!resolved) continue;
        if (!mayRead(*resolved, loc(at), "EXTERNPROTO " + proto.name, options_, diagnostics_)) {
            refused = true;  // warned, as missing: the next url may do
            continue;
        }
        std::error_code ec;
        if (!std::filesystem::is_regular_file(*resolved, ec)) {
            noteMissing(*resolved, options_);
            continue;
        }
        const std::string key = std::filesystem::weakly_canonical(*resolved, ec).string();
        if (std::find(file_stack_.begin(), file_stack_.end(), key) != file_stack_.end() ||
            static_cast<int>(file_stack_.size()) >= vrml97Limits().max_file_depth) {
            diagnostics_.warning(loc(at), "EXTERNPROTO " + proto.name + " refers back to a file being read; skipped");
            return;
        }
        const std::optional<std::string> text = loadText(*resolved, loc(at), options_, diagnostics_);
        if (!text) return;
        if (!isVrml97Text(*text)) {
            diagnostics_.warning(loc(at), "EXTERNPROTO " + proto.name + ": " + *resolved + " is not a VRML97 file; skipped");
            return;
        }
        file_stack_.push_back(key);
        Vrml97Parser other(*text, *resolved, options_, file_stack_, diagnostics_);
        std::vector<NodePtr> ignored;
        const bool ok = other.parse(ignored);
        file_stack_.pop_back();
        if (!ok) return;
        found = wanted.empty() ? other.findTopLevelProto(proto.name) : other.findTopLevelProto(wanted);
        if (!found && wanted.empty()) found = other.firstTopLevelProto();
        if (!found) {
            diagnostics_.warning(loc(at), "EXTERNPROTO " + proto.name + ": no PROTO '" +
                                              (wanted.empty() ? proto.name : wanted) + "' in " + *resolved + "; skipped");
            return;
        }
        // The definition's interface gives the defaults; the declaration only repeats the types.
        proto.interface = found->interface;
        proto.body = found->body;
        proto.unresolved = false;
        return;
    }
    if (refused) return;
    diagnostics_.warning(loc(at), "EXTERNPROTO " + proto.name + " is not a local file; its instances are skipped");
}

void Vrml97Parser::skipRoute(const Token& route) {
    // ROUTE from.field TO to.field; tolerate spaces around the dots.
    int guard = 0;
    while (!isWord(lexer_.peek(), "TO")) {
        if (lexer_.peek().kind != TokenKind::Word && lexer_.peek().kind != TokenKind::Number) fail(lexer_.peek(), "malformed ROUTE");
        lexer_.next();
        if (++guard > 3) fail(route, "malformed ROUTE (no TO)");
    }
    lexer_.next();
    Token target = expect(TokenKind::Word, "a node.field after ROUTE ... TO");
    while (target.text.ends_with('.') || (lexer_.peek().kind == TokenKind::Number && lexer_.peek().text.starts_with('.'))) {
        target = lexer_.next();
        if (target.kind != TokenKind::Word && target.kind != TokenKind::Number) fail(target, "malformed ROUTE");
        if (++guard > 6) fail(route, "malformed ROUTE");
    }
}

void Vrml97Parser::skipBraces(const Token& open_from) {
    int level = 1;
    while (level > 0) {
        const Token t = lexer_.next();
        if (t.kind == TokenKind::OpenBrace) ++level;
        else if (t.kind == TokenKind::CloseBrace) --level;
        else if (t.kind == TokenKind::End) fail(open_from, "this '{' is never closed");
    }
}

void Vrml97Parser::skipValue() {
    // The type is unknown: skip one bracketed list, a run of numbers, a string, a word, or a
    // node (DEF/USE included) with its braces.
    const Token t = lexer_.next();
    switch (t.kind) {
        case TokenKind::OpenBracket: {
            int level = 1;
            while (level > 0) {
                const Token u = lexer_.next();
                if (u.kind == TokenKind::OpenBracket) ++level;
                else if (u.kind == TokenKind::CloseBracket) --level;
                else if (u.kind == TokenKind::End) fail(t, "this '[' is never closed");
            }
            return;
        }
        case TokenKind::Number:
            while (lexer_.peek().kind == TokenKind::Number) lexer_.next();
            return;
        case TokenKind::String:
            return;
        case TokenKind::Word:
            if (t.text == "USE") {
                lexer_.next();
                return;
            }
            if (t.text == "DEF") {
                lexer_.next();
                lexer_.next();
            }
            if (lexer_.peek().kind == TokenKind::OpenBrace) skipBraces(lexer_.next());
            return;
        default:
            fail(t, "expected a field value, found " + describe(t));
    }
}

}  // namespace radbake::vrml
