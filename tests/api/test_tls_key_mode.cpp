// The generated TLS private key (audit, docs/reliability.md): a key regenerated over an old
// file kept that file's 0644 mode, so other users could read it. The key is now 0600 whenever it
// is written or reused, and a data folder the server creates is 0700.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <filesystem>

#include "temp_files.h"
#include "tls_certificate.h"

namespace caliper::server {
namespace {

mode_t mode_of(const std::string& path) {
  struct stat st {};
  EXPECT_EQ(::stat(path.c_str(), &st), 0) << path;
  return st.st_mode & 07777;
}

TEST(TlsCertificate, ThePrivateKeyIsOwnerOnlyAlsoWhenRewritten) {
  test::TempDir dir;
  const mode_t old_mask = ::umask(022);
  const std::string data = dir / "data";
  const CertificateFiles first = ensure_self_signed_certificate(data, {"localhost", "127.0.0.1"});
  EXPECT_TRUE(first.created);
  EXPECT_EQ(mode_of(data), 0700u);
  EXPECT_EQ(mode_of(first.key_file), 0600u);

  // The certificate lost, the key left world-readable: the key is regenerated into that file.
  std::filesystem::remove(first.cert_file);
  ASSERT_EQ(::chmod(first.key_file.c_str(), 0644), 0);
  const CertificateFiles second = ensure_self_signed_certificate(data, {"localhost"});
  EXPECT_TRUE(second.created);
  EXPECT_EQ(mode_of(second.key_file), 0600u);

  // Both files there but the key readable by others: reused, and tightened.
  ASSERT_EQ(::chmod(second.key_file.c_str(), 0644), 0);
  const CertificateFiles third = ensure_self_signed_certificate(data, {"localhost"});
  EXPECT_FALSE(third.created);
  EXPECT_EQ(mode_of(third.key_file), 0600u);
  ::umask(old_mask);
}

}  // namespace
}  // namespace caliper::server
