#pragma once
#include <optional>
// VRML97 classic-encoding parser: text -> node graph (io/vrml/vrml97_nodes.h). PROTO
// instances stay unexpanded (the scene builder expands them); ROUTEs are skipped.
#include <memory>
#include <string>
#include <string_view>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "io/vrml/lexer.h"
#include "io/vrml/vrml97_nodes.h"
#include "io/vrml/vrml_reader.h"

namespace radbake::vrml {

// Bounds that keep hostile files from exhausting the stack, memory or time. Process-wide so
// the fuzz target can lower them; the defaults are far above anything a real scene needs.
struct Vrml97Limits {
    int max_nesting = 200;                   // nested nodes in one file
    int max_file_depth = 32;                 // Inline / EXTERNPROTO chain length
    int max_proto_depth = 64;                // PROTO instances expanding into PROTO instances
    size_t max_expanded_nodes = 2'000'000;   // nodes copied by PROTO expansion, per file
    size_t max_node_visits = 50'000'000;     // nodes the builder walks, per file (DEF/USE fan-out)
    size_t max_triangles = 300'000'000;      // triangles in the scene
};
Vrml97Limits& vrml97Limits();

class Vrml97Parser {
public:
    // `file_stack` holds the files being read (for the EXTERNPROTO recursion guard).
    Vrml97Parser(std::string_view text, std::string path, const VrmlOptions& options,
                 std::vector<std::string>& file_stack, Diagnostics& diagnostics);

    // Parses the whole text. False after reporting at least one located error; `roots` then
    // holds what was read before the error.
    bool parse(std::vector<NodePtr>& roots);

    // The PROTOs declared at the top level of the file (for EXTERNPROTO).
    std::shared_ptr<const ProtoDef> findTopLevelProto(std::string_view name) const;
    std::shared_ptr<const ProtoDef> firstTopLevelProto() const { return first_proto_; }

private:
    struct Scope {
        Scope* parent = nullptr;
        ProtoDef* proto = nullptr;  // the PROTO whose body this is (for IS)
        std::unordered_map<std::string, NodePtr> defs;
        std::unordered_map<std::string, std::shared_ptr<ProtoDef>> protos;
    };

    void parseStatement(Scope& scope, std::vector<NodePtr>& out, int depth);
    NodePtr parseNodeStatement(Scope& scope, int depth);
    NodePtr parseNode(const Token& type, Scope& scope, int depth);
    // The next field name in a node body, after the extras every body accepts (ROUTE, PROTO,
    // IS bindings); nullopt at the closing brace.
    std::optional<Token> nextBodyField(Node& node, Scope& scope, int depth);
    void parseProtoInstanceBody(Node& node, const ProtoDef& proto, Scope& scope, int depth);
    void parseBuiltinBody(Node& node, const NodeSpec& spec, Scope& scope, int depth);
    bool parseBodyExtra(const Token& word, Scope& scope, int depth);  // ROUTE, PROTO, EXTERNPROTO inside a body
    bool parseIs(Node& node, const Token& field_name, Scope& scope);
    void parseValue(FieldType type, FieldValue& value, const Token& field_name, Scope& scope, int depth);
    void parseNumbers(FieldType type, FieldValue& value, const Token& field_name);
    void parseProto(const Token& keyword, Scope& scope, int depth);  // after the keyword
    void parseExternProto(Scope& scope);                              // after the keyword
    void parseInterface(ProtoDef& proto, bool with_values, Scope& scope, int depth);
    void resolveExternProto(ProtoDef& proto, const std::vector<std::string>& urls, const Token& at);
    void skipRoute(const Token& route);                               // after the keyword
    void skipBraces(const Token& open_from);
    void skipValue();
    std::shared_ptr<ProtoDef> findProto(const Scope& scope, std::string_view name) const;

    Token expect(TokenKind kind, const char* what);
    [[noreturn]] void fail(const Token& at, const std::string& message);
    void unknown(const Token& at, const std::string& message);  // warning, or error when strict
    SourceLocation loc(const Token& t) const { return lexer_.location(t); }

    Lexer lexer_;
    std::string path_;
    const VrmlOptions& options_;
    std::vector<std::string>& file_stack_;
    Diagnostics& diagnostics_;
    Scope top_;
    std::shared_ptr<const ProtoDef> first_proto_;
    std::unordered_set<std::string> warned_kinds_;
    bool had_error_ = false;
};

}  // namespace radbake::vrml
