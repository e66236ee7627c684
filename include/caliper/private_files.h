// Files only their owner may read: the capture sessions database (with its SQLite -wal and -shm
// files) and the TLS private key, in a data folder only its owner may enter. Modes are set
// explicitly, whatever the umask, and also on files that already existed with a wider mode.
#pragma once
#include <string>

namespace caliper {

// Creates `dir` and any missing parents. The folder itself gets mode 0700 when this call
// creates it; an existing folder (one the user chose) is left as it is. Throws Error(Io).
void create_private_directory(const std::string& dir);

// Creates `path` empty with mode 0600 when it does not exist; an existing file keeps its
// contents and gets mode 0600 (left as it is if it belongs to another user). Throws Error(Io).
void create_private_file(const std::string& path);

// Sets an existing file's mode to 0600 (nothing when it does not exist or belongs to another
// user). Throws Error(Io) if the mode cannot be set otherwise.
void restrict_to_owner(const std::string& path);

// Writes `bytes` to `path`, created or truncated, with mode 0600 — set before the first byte is
// written, also when the file existed with a wider mode. Throws Error(Io).
void write_private_file(const std::string& path, const std::string& bytes);

}  // namespace caliper
