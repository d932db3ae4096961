// The PLY check before Assimp (src/io/assimp/ply_guard.cpp) through radbake::importScene:
// inputs that make Assimp 5.2.5's PLY importer misbehave end in a located error, ordinary PLY
// files still read (docs/fuzzing.md, findings 5 and 11).
#include <doctest/doctest.h>

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>

#include "io/import.h"
#include "import_test_support.h"

namespace fs = std::filesystem;
using namespace radbake;
using importtest::TempDir;

namespace {

// The one error importScene reports for `bytes` written as input.ply.
Diagnostic refusal(const std::string& bytes) {
    TempDir dir;
    return importtest::refusal(dir.write("input.ply", bytes));
}

// The scene read from `bytes` written as input.ply, which must read without errors.
Scene accepted(const std::string& bytes) {
    TempDir dir;
    Diagnostics diagnostics;
    std::optional<Scene> scene = importScene(dir.write("input.ply", bytes), {}, diagnostics);
    for (const Diagnostic& d : diagnostics.all()) CAPTURE(d.message);
    REQUIRE(scene);
    CHECK(diagnostics.errorCount() == 0);
    return *scene;
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// Binary values in either byte order.
struct Binary {
    bool big_endian = false;
    std::string bytes;
    template <class T>
    Binary& put(T value) {
        char raw[sizeof(T)];
        std::memcpy(raw, &value, sizeof(T));
        if (big_endian != (std::endian::native == std::endian::big)) std::reverse(raw, raw + sizeof(T));
        bytes.append(raw, sizeof(T));
        return *this;
    }
};

enum class Format { Ascii, LittleEndian, BigEndian };

// A unit square as two triangles and, beside it, a quad: 8 vertices with normals, colours
// and texture coordinates, 3 faces (4 triangles), in the given format. `vertex_extra` and
// `face_extra` go into the header after the vertex and face elements (comments, obj_info).
std::string squaresPly(Format format, const std::string& vertex_extra = "", const std::string& face_extra = "") {
    const float p[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {2, 0, 0}, {3, 0, 0}, {3, 1, 0}, {2, 1, 0}};
    const int faces[3][4] = {{0, 1, 2, -1}, {0, 2, 3, -1}, {4, 5, 6, 7}};
    std::string header = "ply\nformat ";
    header += format == Format::Ascii ? "ascii" : format == Format::LittleEndian ? "binary_little_endian" : "binary_big_endian";
    header += " 1.0\ncomment made by hand\nobj_info a comment Assimp does not know\nelement vertex 8\n"
              "property float x\nproperty float y\nproperty float z\nproperty float nx\nproperty float ny\n"
              "property float nz\nproperty uchar red\nproperty uchar green\nproperty uchar blue\n"
              "property float u\nproperty float v\n" +
              vertex_extra + "element face 3\nproperty list uchar int vertex_indices\n" + face_extra + "end_header\n";
    if (format == Format::Ascii) {
        std::string body;
        for (const auto& v : p)
            body += std::to_string(v[0]) + " " + std::to_string(v[1]) + " " + std::to_string(v[2]) + " 0 0 1 200 100 50 " +
                    std::to_string(v[0]) + " " + std::to_string(v[1]) + "\n";
        for (const auto& f : faces) {
            const int n = f[3] < 0 ? 3 : 4;
            body += std::to_string(n);
            for (int i = 0; i < n; ++i) body += " " + std::to_string(f[i]);
            body += "\n";
        }
        return header + body;
    }
    Binary body{format == Format::BigEndian, ""};
    for (const auto& v : p)
        body.put(v[0]).put(v[1]).put(v[2]).put(0.0f).put(0.0f).put(1.0f).put(uint8_t{200}).put(uint8_t{100})
            .put(uint8_t{50}).put(v[0]).put(v[1]);
    for (const auto& f : faces) {
        const int n = f[3] < 0 ? 3 : 4;
        body.put(static_cast<uint8_t>(n));
        for (int i = 0; i < n; ++i) body.put(static_cast<int32_t>(f[i]));
    }
    return header + body.bytes;
}

// The number of a line in `text` where `part` first appears (1-based).
int lineOf(const std::string& text, const std::string& part) {
    const size_t at = text.find(part);
    REQUIRE(at != std::string::npos);
    return 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(at), '\n'));
}

}  // namespace

TEST_CASE("PLY check: ordinary ASCII and binary (both byte orders) files still read") {
    for (const Format format : {Format::Ascii, Format::LittleEndian, Format::BigEndian}) {
        CAPTURE(static_cast<int>(format));
        const Scene scene = accepted(squaresPly(format));
        REQUIRE(scene.meshes.size() == 1);
        const Mesh& mesh = scene.meshes[0];
        CHECK(mesh.positions.size() == 8);
        CHECK(mesh.polygon_count == 3);
        CHECK(mesh.triangles.size() == 4);
        CHECK(mesh.normals.size() == 8);
        CHECK(mesh.uv0.size() == 8);
        CHECK(mesh.vertex_colors.size() == 8);
        // A CRLF file reads the same.
        if (format == Format::Ascii) {
            std::string crlf;
            for (const char c : squaresPly(format)) crlf += c == '\n' ? std::string("\r\n") : std::string(1, c);
            CHECK(accepted(crlf).meshes.at(0).triangles.size() == 4);
        }
    }
}

TEST_CASE("fuzz: a PLY element count that cannot fit in the file is a located error before Assimp reads it") {
    // fuzz_assimp_ply, 30 minutes (docs/fuzzing.md, finding 11): a garbled element line whose
    // name is a long number. Assimp 5.2.5 reads an unknown element's count from the start of
    // its name, modulo 2^32 (1107328640), and reserves that many instances: an out-of-memory
    // report under ASan, std::bad_alloc without.
    const std::string garbled = std::string("ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n"
                                            "property float y\nproperty float z\n") +
                                "element 66666666666666000000 uchar int vertex_indices\nproperty uchar a\nend_header\n" +
                                std::string(36, '\0');
    Diagnostic error = refusal(garbled);
    CHECK(error.location.line == lineOf(garbled, "element 6666"));
    CHECK(error.location.column == 1);
    CHECK(contains(error.message, "'66666666666666000000' declares 1107328640 instances"));
    CHECK(contains(error.message, "but only 36 bytes follow the header"));

    // A plain count too large for the body, binary and ASCII.
    std::string binary = squaresPly(Format::LittleEndian);
    binary.replace(binary.find("vertex 8"), 8, "vertex 4000000000");
    error = refusal(binary);
    CHECK(error.location.line == lineOf(binary, "element vertex"));
    CHECK(contains(error.message, "PLY element 'vertex' declares 4000000000 instances of at least 35 bytes but only"));
    std::string ascii = squaresPly(Format::Ascii);
    ascii.replace(ascii.find("face 3"), 6, "face 3000");
    error = refusal(ascii);
    CHECK(error.location.line == lineOf(ascii, "element face"));
    CHECK(contains(error.message, "PLY element 'face' declares 3000 instances of at least 2 bytes but only"));

    // A count with trailing garbage is what Assimp reads of it, here too large; one that
    // wraps is read modulo 2^32.
    std::string trailing = squaresPly(Format::Ascii);
    trailing.replace(trailing.find("face 3"), 6, "face 1200x");
    CHECK(contains(refusal(trailing).message, "PLY element 'face' declares 1200 instances of at least 2 bytes"));
    std::string wraps = squaresPly(Format::Ascii);
    wraps.replace(wraps.find("face 3"), 6, "face 4294968296");
    CHECK(contains(refusal(wraps).message,
                   "PLY element 'face' declares 1000 instances (Assimp 5.2.5 reads the count from '4294968296' modulo 2^32)"));

    // Elements without properties take a byte each: Assimp loops once per instance.
    const std::string empty_elements = squaresPly(Format::LittleEndian, "", "element edge 100000\n");
    error = refusal(empty_elements);
    CHECK(error.location.line == lineOf(empty_elements, "element edge"));
    CHECK(contains(error.message, "PLY element 'edge' declares 100000 instances but only 323 bytes follow the header"));

    // Each element fits, all of them together do not.
    const std::string together =
        "ply\nformat binary_little_endian 1.0\nelement edge 30\nelement edge 30\nend_header\n" + std::string(40, '\0');
    error = refusal(together);
    CHECK(error.location.line == 4);
    CHECK(contains(error.message, "'edge' declares 30 instances, 60 instances in all up to here of at least 60 "
                                  "bytes, but only 40 bytes follow the header"));

    // Assimp reads the count of an element it does not know from the start of its name, so
    // a large count after an ordinary name is no count at all to it, and harmless.
    CHECK(accepted(squaresPly(Format::LittleEndian, "", "element unknown 4000000000\n")).meshes.at(0).triangles.size() == 4);
}

TEST_CASE("fuzz: PLY magic after blank lines is still checked (Assimp skips them)") {
    // Assimp's PLY importer finds the magic on the first line after any line ends, so a file
    // starting with a line end still reaches it: finding 2a's input behind a '\n' was a SEGV.
    for (const std::string& text : {std::string("\nply\nformat binary_tm\0\0", 23), std::string("\r\nply\nformat binary_tm\0\0", 24)}) {
        const Diagnostic error = refusal(text);
        CHECK(error.location.line == 2);
        CHECK(contains(error.message, "end_header"));
    }
    CHECK(accepted("\n" + squaresPly(Format::Ascii)).meshes.at(0).triangles.size() == 4);
}

TEST_CASE("fuzz: a PLY file with a second face or vertex element is a located error before Assimp reads it") {
    // fuzz_assimp_ply (docs/fuzzing.md, finding 5), minimized: two face elements. Assimp
    // 5.2.5 reads every face element into the face array of the first, at each instance's
    // index within its own element: the second face's index array replaces the first's, which
    // leaks (the body is short, so the lists' lengths come from Assimp's '\n' padding).
    const std::string minimized("ply\nformat binary_ rpe\nelement vertex 4\nproperty float x\np nz\nelement face 1\n"
                                "property list uchar int vertex_indices\nz\nelement face 1\n"
                                "property list uchar int vertex_indices\nend_header\n\0\x03",
                                185);
    Diagnostic error = refusal(minimized);
    CHECK(error.location.line == 9);
    CHECK(error.location.column == 1);
    CHECK(contains(error.message, "PLY element 'face' is a second face element (the first, 'face', is on line 6)"));

    // The same with a body that holds every value: a triangle, then a second face element.
    Binary body;
    body.put(0.0f).put(0.0f).put(0.0f).put(1.0f).put(0.0f).put(0.0f).put(0.0f).put(1.0f).put(0.0f);
    body.put(uint8_t{3}).put(int32_t{0}).put(int32_t{1}).put(int32_t{2});
    body.put(uint8_t{3}).put(int32_t{2}).put(int32_t{1}).put(int32_t{0});
    body.put(uint8_t{3}).put(int32_t{0}).put(int32_t{2}).put(int32_t{1});
    const std::string faces = "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n"
                              "property float y\nproperty float z\nelement face 1\n"
                              "property list uchar int vertex_indices\nelement face 2\n"
                              "property list uchar int vertex_indices\nend_header\n" +
                              body.bytes;
    error = refusal(faces);
    CHECK(error.location.line == 9);
    CHECK(contains(error.message, "is a second face element"));

    // A tristrips element after a face element goes to the same array.
    std::string strips = squaresPly(Format::Ascii, "", "element tristrips 1\nproperty list int int vertex_indices\n");
    strips += "3 0 1 2\n";
    error = refusal(strips);
    CHECK(error.location.line == lineOf(strips, "element tristrips"));
    CHECK(contains(error.message, "PLY element 'tristrips' is a second face element (the first, 'face', is on line"));

    // A second vertex element: Assimp writes its instances into the first one's arrays, past
    // their end when it is longer (heap corruption Assimp's own code does not notice).
    std::string vertices = squaresPly(Format::Ascii, "element vertex 20\nproperty float x\nproperty float y\nproperty float z\n");
    const size_t faces_at = vertices.find("3 0 1 2\n");
    for (int i = 0; i < 20; ++i) vertices.insert(faces_at, "1 1 1\n");
    error = refusal(vertices);
    CHECK(error.location.line == lineOf(vertices, "element vertex 20"));
    CHECK(contains(error.message, "PLY element 'vertex' is a second vertex element (the first, 'vertex', is on line 5)"));
}

TEST_CASE("PLY triangle strips are a located error: Assimp 5.2.5 keeps one triangle of each") {
    // PLYImporter::LoadFace writes every triangle of a strip to the same face, leaking the
    // one before (found reading its source). The strip 0 1 2 3 4 (three triangles) comes out
    // as one.
    std::string strips = "ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\nproperty float y\nproperty float z\n"
                         "element tristrips 1\nproperty list int int vertex_indices\nend_header\n"
                         "0 0 0\n1 0 0\n0 1 0\n1 1 0\n0 2 0\n5 0 1 2 3 4\n";
    const Diagnostic error = refusal(strips);
    CHECK(error.location.line == 7);
    CHECK(contains(error.message, "PLY element 'tristrips' is not read"));
}

TEST_CASE("PLY properties Assimp 5.2.5 reads through missing others are a located error") {
    // Found reading PlyLoader.cpp: a face's texcoord list is read through its vertex_indices
    // list (without one, through a null pointer: SEGV), a material's opacity at the index of
    // its specular_power (without one, an exception after the mesh is built: it leaks).
    const std::string vertices = "element vertex 3\nproperty float x\nproperty float y\nproperty float z\n";
    const std::string texcoords = "ply\nformat ascii 1.0\n" + vertices +
                                  "element face 1\nproperty list uchar float texcoord\nend_header\n"
                                  "0 0 0\n1 0 0\n0 1 0\n6 0 0 1 0 0 1\n";
    Diagnostic error = refusal(texcoords);
    CHECK(error.location.line == 7);
    CHECK(contains(error.message, "PLY element 'face' has a texcoord list but no vertex_indices list"));
    const std::string opacity = "ply\nformat ascii 1.0\n" + vertices +
                                "element face 1\nproperty list uchar int vertex_indices\n"
                                "element material 1\nproperty float opacity\nend_header\n"
                                "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n0.5\n";
    error = refusal(opacity);
    CHECK(error.location.line == 9);
    CHECK(contains(error.message, "PLY element 'material' has an opacity but no specular_power property"));

    // With both, each reads.
    std::string both = texcoords;
    both.replace(both.find("property list uchar float texcoord"), 0, "property list uchar int vertex_indices\n");
    both.replace(both.find("6 0 0 1"), 0, "3 0 1 2 ");
    CHECK(accepted(both).meshes.at(0).triangles.size() == 1);
    std::string phong = opacity;
    phong.replace(phong.find("property float opacity"), 0, "property float specular_power\n");
    phong.replace(phong.find("0.5\n"), 0, "2 ");
    CHECK(accepted(phong).meshes.at(0).triangles.size() == 1);
}

TEST_CASE("fuzz: binary PLY data that runs past the end of the file is a located error before Assimp reads it") {
    // Past the file's end Assimp 5.2.5 reads the '\n' bytes its buffer starts with, as values
    // and as list lengths, and once past its buffer throws "File corrupted", leaking the mesh
    // (found with fuzz_assimp_ply's build).
    std::string truncated = squaresPly(Format::LittleEndian);
    truncated.resize(truncated.size() - 4);  // the quad's last index
    Diagnostic error = refusal(truncated);
    CHECK(error.location.line == lineOf(truncated, "element face"));
    CHECK(contains(error.message, "PLY element 'face' runs past the end of the file: its instance 3 of 3 has a list "
                                  "'vertex_indices' of 4 entries, more than the file's last 12 bytes hold"));
    // Values of fixed size after the lists, big endian: the lists take more than the counts
    // alone tell, so the last edge is cut.
    std::string edges = squaresPly(Format::BigEndian, "", "element edge 2\nproperty int vertex1\nproperty int vertex2\n");
    edges += std::string(12, '\0');
    error = refusal(edges);
    CHECK(error.location.line == lineOf(edges, "element edge"));
    CHECK(contains(error.message, "PLY element 'edge' runs past the end of the file: its instance 2 of 2 ends after "
                                  "the file's last byte"));

    // A list length Assimp reads as 4294967295 (an int -1), reserved before the entries are read.
    const std::string header = "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                               "property float z\nelement face 1\nproperty list int int vertex_indices\nend_header\n";
    Binary body;
    for (int i = 0; i < 9; ++i) body.put(0.0f);
    body.put(int32_t{-1}).put(int32_t{0}).put(int32_t{1}).put(int32_t{2});
    error = refusal(header + body.bytes);
    CHECK(error.location.line == 7);
    CHECK(contains(error.message, "list 'vertex_indices' of 4294967295 entries"));

    // A list length that is a float: Assimp converts it to unsigned int unchecked.
    std::string float_length = header;
    float_length.replace(float_length.find("list int int"), 12, "list float int");
    Binary float_body;
    for (int i = 0; i < 9; ++i) float_body.put(0.0f);
    float_body.put(1e10f).put(int32_t{0}).put(int32_t{1}).put(int32_t{2});
    error = refusal(float_length + float_body.bytes);
    CHECK(error.location.line == 7);
    CHECK(contains(error.message, "has a list 'vertex_indices' whose length is a floating-point number"));

    // Lengths of other sizes, in both byte orders, still read.
    for (const bool big_endian : {false, true}) {
        std::string lengths = header;
        lengths.replace(lengths.find("little"), 6, big_endian ? "big" : "little");
        lengths.replace(lengths.find("list int int"), 12, "list ushort uint");
        Binary triangle{big_endian, ""};
        triangle.put(0.0f).put(0.0f).put(0.0f).put(1.0f).put(0.0f).put(0.0f).put(0.0f).put(1.0f).put(0.0f);
        triangle.put(uint16_t{3}).put(uint32_t{0}).put(uint32_t{1}).put(uint32_t{2});
        CHECK(accepted(lengths + triangle.bytes).meshes.at(0).triangles.size() == 1);
    }
}

TEST_CASE("fuzz: ASCII PLY values Assimp throws on, lists longer than their line, missing lines: located errors") {
    // Assimp 5.2.5's ASCII number parser throws on a value that is not a number, after the
    // mesh is built, which then leaks (found with fuzz_assimp_ply's build); a list's length
    // is reserved before its entries are read (a char -1 is 4294967295 entries); an instance
    // past the last line parses that line again.
    std::string garbage = squaresPly(Format::Ascii);
    const size_t second_vertex = garbage.find("\n1.000000 0.000000 0.000000") + 1;
    garbage.replace(second_vertex + 18, 8, "zz");
    Diagnostic error = refusal(garbage);
    CHECK(error.location.line == lineOf(garbage, "1.000000 0.000000 zz"));
    CHECK(error.location.column == 19);
    CHECK(contains(error.message, "PLY element 'vertex' instance 2 of 8: Assimp 5.2.5 cannot read 'zz' as a number for 'z'"));
    std::string exponent = squaresPly(Format::Ascii);
    exponent.replace(exponent.find(" 200 100 50 "), 0, "e");  // the first vertex's nz reads "1e"
    CHECK(contains(refusal(exponent).message, "cannot read '1e' as a number for 'nz'"));

    std::string long_list = squaresPly(Format::Ascii);
    long_list.replace(long_list.find("list uchar int"), 14, "list char int");
    long_list.replace(long_list.find("\n3 0 1 2\n") + 1, 1, "-1");
    error = refusal(long_list);
    CHECK(error.location.line == lineOf(long_list, "-1 0 1 2"));
    CHECK(error.location.column == 1);
    CHECK(contains(error.message, "PLY element 'face' instance 1 of 3 has a list 'vertex_indices' of 4294967295 entries "
                                  "on a line with room for 6"));

    std::string short_body = squaresPly(Format::Ascii);
    short_body.resize(short_body.rfind("4 4 5 6 7"));  // the quad's line
    error = refusal(short_body);
    CHECK(error.location.line == lineOf(short_body, "element face"));
    CHECK(contains(error.message, "PLY element 'face' declares 3 instances, a line each, but the file ends before instance 3"));

    // Numbers Assimp reads: signs, exponents.
    std::string numbers = squaresPly(Format::Ascii);
    numbers.replace(numbers.find("\n0.000000 0.000000 0.000000") + 1, 26, "-0.0e+0 +0 0.0e-3");
    CHECK(accepted(numbers).meshes.at(0).triangles.size() == 4);
}
