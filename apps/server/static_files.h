// Static files of the web front end: a URL path is mapped to a file strictly inside the web root.
// Anything that could step outside it — "..", ".", backslashes, NUL, percent signs left after
// decoding (double encoding), absolute paths, symlinks leading out — is refused.
#pragma once
#include <optional>
#include <string>

namespace caliper::server {

// The file for a decoded URL path ("/" → index.html), or nullopt when the path is refused or no
// such regular file exists inside `web_root`.
std::optional<std::string> resolve_static_path(const std::string& web_root, const std::string& url_path);

// MIME type by file extension (text types with charset=utf-8); application/octet-stream otherwise.
std::string mime_type_for(const std::string& path);

}  // namespace caliper::server
