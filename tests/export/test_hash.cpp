// SHA-256 against the FIPS 180-2 example vectors, in memory and streamed from files.
#include <doctest/doctest.h>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>

#include "export/hash.h"

using namespace radbake;
namespace fs = std::filesystem;

namespace {
const char* const kAbc = "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad";
const char* const kEmpty = "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855";
const char* const k448Bits = "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1";
const char* const k448Message = "abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq";
const char* const kMillionA = "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0";

struct TempFile {
    fs::path path;
    explicit TempFile(const std::string& content) {
        std::string pattern = (fs::temp_directory_path() / "radbake-hash-XXXXXX").string();
        const int fd = mkstemp(pattern.data());
        REQUIRE(fd >= 0);
        close(fd);
        path = pattern;
        std::ofstream(path, std::ios::binary) << content;
    }
    ~TempFile() {
        std::error_code ec;
        fs::remove(path, ec);
    }
};
}  // namespace

TEST_CASE("sha256Hex gives the FIPS 180-2 digests") {
    CHECK(sha256Hex("abc") == kAbc);
    CHECK(sha256Hex("") == kEmpty);
    CHECK(sha256Hex(k448Message) == k448Bits);
    CHECK(sha256Hex(std::string(1000000, 'a')) == kMillionA);
}

TEST_CASE("sha256File streams a file and matches the in-memory digest") {
    Diagnostics diagnostics;
    for (const auto& [content, digest] : {std::pair<std::string, const char*>{"abc", kAbc},
                                          {"", kEmpty},
                                          {k448Message, k448Bits},
                                          {std::string(1000000, 'a'), kMillionA}}) {  // many read blocks
        TempFile file(content);
        const std::optional<std::string> got = sha256File(file.path, diagnostics);
        REQUIRE(got.has_value());
        CHECK(*got == digest);
    }
    CHECK(diagnostics.all().empty());
}

TEST_CASE("sha256File reports a missing file and a directory at their paths") {
    Diagnostics diagnostics;
    const fs::path missing = fs::temp_directory_path() / "radbake-hash-no-such-file";
    CHECK_FALSE(sha256File(missing, diagnostics).has_value());
    REQUIRE(diagnostics.errorCount() == 1);
    CHECK(diagnostics.all()[0].location.file == missing.string());
    CHECK(diagnostics.all()[0].message == "cannot open file to hash it: no such file");

    const fs::path directory = fs::temp_directory_path();
    CHECK_FALSE(sha256File(directory, diagnostics).has_value());
    REQUIRE(diagnostics.errorCount() == 2);
    CHECK(diagnostics.all()[1].location.file == directory.string());
    CHECK(diagnostics.all()[1].message == "cannot open file to hash it: not a regular file (a directory)");
}

TEST_CASE("sha256File never reads a FIFO: it is refused by name, not waited on") {
    std::string pattern = (fs::temp_directory_path() / "radbake-hash-XXXXXX").string();
    REQUIRE(::mkdtemp(pattern.data()) != nullptr);
    const fs::path fifo = fs::path(pattern) / "fifo";
    REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
    // A writer that feeds whoever opens the FIFO: a hash that read it would succeed.
    std::thread writer([&] {
        if (std::FILE* file = std::fopen(fifo.c_str(), "wb")) {
            std::fputs("bytes", file);
            std::fclose(file);
        }
    });
    Diagnostics diagnostics;
    const std::optional<std::string> hash = sha256File(fifo, diagnostics);
    // Releases the writer when the hash did not open the FIFO (it waits for a reader).
    const int reader = ::open(fifo.c_str(), O_RDONLY | O_NONBLOCK);
    writer.join();
    if (reader >= 0) ::close(reader);
    fs::remove_all(pattern);
    CHECK_FALSE(hash.has_value());
    REQUIRE(diagnostics.errorCount() == 1);
    CHECK(diagnostics.all()[0].location.file == fifo.string());
    CHECK(diagnostics.all()[0].message == "cannot open file to hash it: not a regular file (a FIFO)");
}
