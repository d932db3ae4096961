// The read policy's check (core/read_policy.h): resolved paths, compared by whole components.
#include <doctest/doctest.h>
#include <stdlib.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "core/read_policy.h"

namespace fs = std::filesystem;
using radbake::readPolicyFor;

TEST_CASE("read policy: under the scene's folder by whole components, symbolic links resolved, missing files allowed") {
    std::string pattern = (fs::temp_directory_path() / "radbake-policy-XXXXXX").string();
    REQUIRE(mkdtemp(pattern.data()) != nullptr);
    const fs::path tmp = pattern;
    fs::create_directories(tmp / "scene" / "sub");
    fs::create_directories(tmp / "scene2");
    std::ofstream(tmp / "scene" / "room.wrl") << "#VRML V2.0 utf8\n";
    std::ofstream(tmp / "scene2" / "other.wrl") << "#VRML V2.0 utf8\n";
    REQUIRE_MESSAGE(::symlink((tmp / "scene2").c_str(), (tmp / "scene" / "out").c_str()) == 0, std::strerror(errno));

    const auto policy = readPolicyFor((tmp / "scene" / "room.wrl").string(), {});
    CHECK(policy.whyRefused((tmp / "scene" / "room.wrl").string()).empty());
    CHECK(policy.whyRefused((tmp / "scene" / "sub" / ".." / "missing.png").string()).empty());  // missing: the caller's
    CHECK(policy.whyRefused((tmp / "scene" / "sub").string()).find("a directory") != std::string::npos);
    // A sibling whose name starts like the root's is outside it.
    CHECK(policy.whyOutside((tmp / "scene2" / "other.wrl").string()).find("outside the read root") != std::string::npos);
    CHECK_FALSE(policy.whyOutside((tmp / "scene" / ".." / "scene2" / "other.wrl").string()).empty());
    CHECK(policy.whyOutside((tmp / "scene" / "out" / "other.wrl").string()).find("resolved to '" +
                                                                                 (tmp / "scene2" / "other.wrl").string()) !=
          std::string::npos);
    CHECK_FALSE(policy.whyOutside("/etc/passwd").empty());
    // A second root widens it.
    const auto widened = readPolicyFor((tmp / "scene" / "room.wrl").string(), {(tmp / "scene2").string()});
    CHECK(widened.whyRefused((tmp / "scene" / "out" / "other.wrl").string()).empty());
    CHECK(widened.whyOutside("/etc/passwd").find("outside every read root") != std::string::npos);
    fs::remove_all(tmp);
}

TEST_CASE("read policy: the file actually opened is checked, so a path swapped for a link after the check is refused") {
    std::string pattern = (fs::temp_directory_path() / "radbake-policy-XXXXXX").string();
    REQUIRE(mkdtemp(pattern.data()) != nullptr);
    const fs::path tmp = pattern;
    fs::create_directories(tmp / "scene");
    fs::create_directories(tmp / "secret");
    std::ofstream(tmp / "scene" / "room.wrl") << "#VRML V2.0 utf8\n";
    std::ofstream(tmp / "scene" / "inline.wrl") << "#VRML V2.0 utf8\n";
    std::ofstream(tmp / "secret" / "key.txt") << "not for a scene\n";
    const auto policy = readPolicyFor((tmp / "scene" / "room.wrl").string(), {});

    std::string why;
    CHECK(radbake::readRegularFile((tmp / "scene" / "inline.wrl").string(), why, SIZE_MAX, policy.openedCheck()));
    // The swap: the name passed the check as a file in the tree, then became a link out of it.
    const fs::path swapped = tmp / "scene" / "texture.png";
    std::ofstream(swapped) << "image";
    REQUIRE(policy.whyRefused(swapped.string()).empty());
    fs::remove(swapped);
    REQUIRE_MESSAGE(::symlink((tmp / "secret" / "key.txt").c_str(), swapped.c_str()) == 0, std::strerror(errno));
    CHECK_FALSE(radbake::readRegularFile(swapped.string(), why, SIZE_MAX, policy.openedCheck()));
    CHECK(why.find("opened '" + (tmp / "secret" / "key.txt").string() + "', outside the read roots") != std::string::npos);
    CHECK_FALSE(radbake::openRegularFile(swapped.string(), why, SIZE_MAX, policy.openedCheck()));
    // Without the check the same open succeeds: the check is what refuses it.
    CHECK(radbake::readRegularFile(swapped.string(), why));

    // The scene file itself is read wherever it leads.
    const fs::path linked_scene = tmp / "scene" / "linked.wrl";
    REQUIRE(::symlink((tmp / "secret" / "key.txt").c_str(), linked_scene.c_str()) == 0);
    const auto linked_policy = readPolicyFor(linked_scene.string(), {});
    CHECK(radbake::readRegularFile(linked_scene.string(), why, SIZE_MAX, linked_policy.openedCheck()));
    fs::remove_all(tmp);
}
