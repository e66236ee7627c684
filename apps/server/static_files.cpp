#include "static_files.h"

#include <algorithm>
#include <filesystem>
#include <system_error>

namespace caliper::server {

namespace fs = std::filesystem;

std::optional<std::string> resolve_static_path(const std::string& web_root, const std::string& url_path) {
  if (web_root.empty() || url_path.empty() || url_path.front() != '/') return std::nullopt;
  std::string rel = url_path.substr(1);
  if (rel.empty() || rel.back() == '/') rel += "index.html";
  // Refuse by characters first: the path has been percent-decoded once already, so a '%' left here
  // means double encoding (e.g. %252e%252e); a backslash or control character has no business in
  // a file name we serve.
  for (unsigned char c : rel)
    if (c < 0x20 || c == 0x7f || c == '\\' || c == '%' || c == ':') return std::nullopt;
  // Then by segments: no ".", "..", empty segments (//) or hidden files.
  size_t start = 0;
  while (start <= rel.size()) {
    const size_t end = std::min(rel.find('/', start), rel.size());
    const std::string segment = rel.substr(start, end - start);
    if (segment.empty() || segment.front() == '.') return std::nullopt;
    start = end + 1;
  }
  // Finally by location: the real path (symlinks resolved) must lie inside the real web root.
  std::error_code ec;
  const fs::path root = fs::canonical(web_root, ec);
  if (ec) return std::nullopt;
  const fs::path file = fs::canonical(root / rel, ec);
  if (ec) return std::nullopt;
  const std::string root_text = root.string() + "/";
  const std::string file_text = file.string();
  if (file_text.compare(0, root_text.size(), root_text) != 0) return std::nullopt;
  if (!fs::is_regular_file(file, ec)) return std::nullopt;
  return file_text;
}

std::string mime_type_for(const std::string& path) {
  const std::string ext = fs::path(path).extension().string();
  if (ext == ".html") return "text/html; charset=utf-8";
  if (ext == ".js" || ext == ".mjs") return "text/javascript; charset=utf-8";
  if (ext == ".css") return "text/css; charset=utf-8";
  if (ext == ".json" || ext == ".map") return "application/json";
  if (ext == ".svg") return "image/svg+xml";
  if (ext == ".png") return "image/png";
  if (ext == ".ico") return "image/x-icon";
  if (ext == ".txt" || ext == ".md") return "text/plain; charset=utf-8";
  if (ext == ".glb") return "model/gltf-binary";
  if (ext == ".woff2") return "font/woff2";
  return "application/octet-stream";
}

}  // namespace caliper::server
