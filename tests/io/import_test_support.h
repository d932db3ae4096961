#pragma once
// Helpers of the import tests: a fresh folder to write literal files into, and the one located
// error an import of a file must end in.
#include <doctest/doctest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "io/import.h"

namespace importtest {

namespace fs = std::filesystem;

// A fresh directory per test, removed afterwards.
struct TempDir {
    fs::path path;
    TempDir() {
        path = fs::temp_directory_path() / ("radbake_import_" + std::to_string(::getpid()) + "_" +
                                            std::to_string(counter()++));
        fs::remove_all(path);
        fs::create_directories(path);
    }
    ~TempDir() {
        std::error_code ec;
        fs::remove_all(path, ec);
    }
    static int& counter() {
        static int value = 0;
        return value;
    }
    std::string write(const std::string& name, const std::string& text) const {
        const fs::path file = path / name;
        std::ofstream(file, std::ios::binary) << text;
        return file.string();
    }
};

// The error importScene reports for the file at `path`, which must fail with one error there.
inline radbake::Diagnostic refusal(const std::string& path) {
    radbake::Diagnostics diagnostics;
    CHECK_FALSE(radbake::importScene(path, {}, diagnostics));
    REQUIRE(diagnostics.errorCount() == 1);
    const radbake::Diagnostic error = diagnostics.all().back();
    CHECK(error.location.file == path);
    return error;
}

}  // namespace importtest
