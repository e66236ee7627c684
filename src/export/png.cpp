// Minimal PNG writer (PNG specification, ISO/IEC 15948): signature, IHDR, one IDAT holding the
// zlib stream of the filtered rows, IEND. 8-bit truecolour, no interlace. Every row uses filter
// type 0 (None): simple to verify, and the pictures are small enough that size hardly matters.
#include <zlib.h>

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "caliper/errors.h"
#include "caliper/export/render.h"

namespace caliper {
namespace {

void put_u32(std::string& out, std::uint32_t v) {
  out.push_back(static_cast<char>((v >> 24) & 0xff));
  out.push_back(static_cast<char>((v >> 16) & 0xff));
  out.push_back(static_cast<char>((v >> 8) & 0xff));
  out.push_back(static_cast<char>(v & 0xff));
}

// Length, type, data, then the CRC-32 of type + data.
void put_chunk(std::string& out, const char type[4], const std::string& data) {
  put_u32(out, static_cast<std::uint32_t>(data.size()));
  const size_t type_at = out.size();
  out.append(type, 4);
  out += data;
  uLong crc = crc32(0L, Z_NULL, 0);
  crc = crc32(crc, reinterpret_cast<const Bytef*>(out.data() + type_at), static_cast<uInt>(4 + data.size()));
  put_u32(out, static_cast<std::uint32_t>(crc));
}

}  // namespace

std::string encode_png_rgb8(int width, int height, const std::vector<std::uint8_t>& rgb) {
  if (width <= 0 || height <= 0 || width > 65535 || height > 65535)
    throw Error(ErrorKind::InvalidArgument, "PNG size must be 1..65535 pixels per side", "width");
  const size_t row_bytes = static_cast<size_t>(width) * 3;
  if (rgb.size() != row_bytes * static_cast<size_t>(height))
    throw Error(ErrorKind::InvalidArgument, "PNG pixel buffer must hold width*height*3 bytes", "rgb");

  std::string raw;
  raw.reserve((row_bytes + 1) * static_cast<size_t>(height));
  for (int y = 0; y < height; ++y) {
    raw.push_back('\0');  // filter type 0
    raw.append(reinterpret_cast<const char*>(rgb.data()) + row_bytes * static_cast<size_t>(y), row_bytes);
  }
  if (raw.size() > std::numeric_limits<uLong>::max() / 2)
    throw Error(ErrorKind::InvalidArgument, "image too large for PNG encoding", "width");
  uLongf packed_size = compressBound(static_cast<uLong>(raw.size()));
  std::string packed(packed_size, '\0');
  if (compress2(reinterpret_cast<Bytef*>(packed.data()), &packed_size,
                reinterpret_cast<const Bytef*>(raw.data()), static_cast<uLong>(raw.size()), 6) != Z_OK)
    throw Error(ErrorKind::Io, "zlib compression failed while encoding PNG", "rgb");
  packed.resize(packed_size);

  std::string png("\x89PNG\r\n\x1a\n", 8);
  std::string ihdr;
  put_u32(ihdr, static_cast<std::uint32_t>(width));
  put_u32(ihdr, static_cast<std::uint32_t>(height));
  ihdr += std::string("\x08\x02\x00\x00\x00", 5);  // bit depth 8, colour type 2 (RGB), deflate, filter 0, no interlace
  put_chunk(png, "IHDR", ihdr);
  put_chunk(png, "IDAT", packed);
  put_chunk(png, "IEND", {});
  return png;
}

}  // namespace caliper
