// Owner-only files and folders with POSIX calls: the mode is given at creation (so no moment
// exists when another user could open the file) and set again with fchmod for files that existed.
#include "caliper/private_files.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>

#include "caliper/errors.h"

namespace caliper {

namespace {

constexpr mode_t kOwnerFile = 0600;
constexpr mode_t kOwnerFolder = 0700;

[[noreturn]] void fail(const std::string& what, const std::string& path) {
  throw Error(ErrorKind::Io, "cannot " + what + " '" + path + "': " + std::strerror(errno), path);
}

// Opens (creating with mode 0600 if needed) and makes sure the mode is 0600 before returning.
int open_private(const std::string& path, int flags) {
  const int fd = ::open(path.c_str(), flags | O_CREAT | O_CLOEXEC, kOwnerFile);
  if (fd < 0) fail("open", path);
  struct stat st {};
  if (::fstat(fd, &st) == 0 && st.st_uid == ::geteuid() && (st.st_mode & 07777) != kOwnerFile &&
      ::fchmod(fd, kOwnerFile) != 0) {
    ::close(fd);
    fail("restrict the permissions of", path);
  }
  return fd;
}

}  // namespace

void create_private_directory(const std::string& dir) {
  std::error_code ec;
  if (dir.empty() || std::filesystem::is_directory(dir, ec)) return;
  const std::filesystem::path parent = std::filesystem::path(dir).parent_path();
  if (!parent.empty()) std::filesystem::create_directories(parent, ec);  // parents: the usual mode
  if (::mkdir(dir.c_str(), kOwnerFolder) != 0 && errno != EEXIST) fail("create the folder", dir);
}

void create_private_file(const std::string& path) { ::close(open_private(path, O_RDONLY)); }

void restrict_to_owner(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0 || !S_ISREG(st.st_mode) || st.st_uid != ::geteuid()) return;
  if ((st.st_mode & 07777) != kOwnerFile && ::chmod(path.c_str(), kOwnerFile) != 0)
    fail("restrict the permissions of", path);
}

void write_private_file(const std::string& path, const std::string& bytes) {
  const int fd = open_private(path, O_WRONLY | O_TRUNC);
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      ::close(fd);
      fail("write", path);
    }
    done += static_cast<std::size_t>(n);
  }
  if (::close(fd) != 0) fail("write", path);
}

}  // namespace caliper
