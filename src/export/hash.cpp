#include "export/hash.h"

#include <openssl/evp.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>
#include <vector>

#include "core/regular_file.h"

namespace radbake {

namespace {

struct DigestContextFree {
    void operator()(EVP_MD_CTX* context) const { EVP_MD_CTX_free(context); }
};
using DigestContext = std::unique_ptr<EVP_MD_CTX, DigestContextFree>;

std::string hex(const unsigned char* digest, unsigned length) {
    static constexpr char kDigits[] = "0123456789abcdef";
    std::string out(2 * length, '0');
    for (unsigned i = 0; i < length; ++i) {
        out[2 * i] = kDigits[digest[i] >> 4];
        out[2 * i + 1] = kDigits[digest[i] & 15];
    }
    return out;
}

// Incremental SHA-256 through OpenSSL's EVP interface; every call reports success.
class Sha256 {
public:
    Sha256() : context_(EVP_MD_CTX_new()) {
        ok_ = context_ && EVP_DigestInit_ex(context_.get(), EVP_sha256(), nullptr) == 1;
    }
    void update(const void* data, size_t size) {
        if (ok_ && size > 0) ok_ = EVP_DigestUpdate(context_.get(), data, size) == 1;
    }
    // Empty when OpenSSL failed (out of memory): callers treat that as an error.
    std::string finish() {
        unsigned char digest[EVP_MAX_MD_SIZE];
        unsigned length = 0;
        if (!ok_ || EVP_DigestFinal_ex(context_.get(), digest, &length) != 1) return {};
        return hex(digest, length);
    }

private:
    DigestContext context_;
    bool ok_ = false;
};

}  // namespace

std::string sha256Hex(std::string_view bytes) {
    Sha256 sha;
    sha.update(bytes.data(), bytes.size());
    return sha.finish();
}

std::optional<std::string> sha256File(const std::filesystem::path& path, Diagnostics& diagnostics) {
    const SourceLocation where{path.string(), 0, 0};
    // Never a FIFO (open would wait for a writer) or a device (/dev/zero never ends).
    std::string why;
    const InputFile file = openRegularFile(path.string(), why);
    if (!file) {
        diagnostics.error(where, "cannot open file to hash it: " + why);
        return std::nullopt;
    }
    Sha256 sha;
    std::vector<char> block(1 << 16);
    size_t got = 0;
    while ((got = std::fread(block.data(), 1, block.size(), file.get())) > 0) sha.update(block.data(), got);
    const bool read_error = std::ferror(file.get()) != 0;
    const int saved_errno = errno;
    if (read_error) {
        diagnostics.error(where, std::string("cannot read file to hash it: ") + std::strerror(saved_errno));
        return std::nullopt;
    }
    std::string digest = sha.finish();
    if (digest.empty()) {
        diagnostics.error(where, "cannot compute SHA-256 (OpenSSL failed)");
        return std::nullopt;
    }
    return digest;
}

}  // namespace radbake
