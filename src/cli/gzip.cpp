#include "cli/gzip.hpp"

#include <zlib.h>

#include <algorithm>
#include <stdexcept>
#include <string>
#include <vector>

#include "heightmarch/error.hpp"
#include "heightmarch/memory_budget.hpp"

namespace heightmarch::cli {

namespace {

constexpr std::size_t kChunk = std::size_t(1) << 16;  // bytes zlib works on at a time
constexpr std::size_t kFeed = std::size_t(1) << 30;   // bytes handed to zlib at once (its counts are 32-bit)

}  // namespace

std::string gzip(const std::string& text) {
  struct Deflater {
    z_stream z{};
    ~Deflater() { deflateEnd(&z); }
  } deflater;
  z_stream& z = deflater.z;
  // 16 + MAX_WBITS: a gzip header (no name, time 0) and trailer around the deflate stream.
  if (deflateInit2(&z, Z_BEST_COMPRESSION, Z_DEFLATED, 16 + MAX_WBITS, 9, Z_DEFAULT_STRATEGY) != Z_OK)
    throw std::runtime_error("zlib cannot start");
  std::string out;
  std::vector<char> buffer(kChunk);
  std::size_t fed = 0;
  int status = Z_OK;
  while (status != Z_STREAM_END) {  // each pass consumes input or makes output, or ends the stream
    if (z.avail_in == 0 && fed < text.size()) {
      const std::size_t n = std::min(text.size() - fed, kFeed);
      z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(text.data() + fed));
      z.avail_in = uInt(n);
      fed += n;
    }
    z.next_out = reinterpret_cast<Bytef*>(buffer.data());
    z.avail_out = uInt(buffer.size());
    status = deflate(&z, fed == text.size() && z.avail_in == 0 ? Z_FINISH : Z_NO_FLUSH);
    if (status != Z_OK && status != Z_STREAM_END)  // with room for output it always makes progress
      throw std::runtime_error("zlib failed to compress");
    out.append(buffer.data(), buffer.size() - z.avail_out);
  }
  return out;
}

std::string gunzip(const std::string& packed, const std::string& path, std::uintmax_t limit,
                   double parse_factor) {
  struct Inflater {
    z_stream z{};
    ~Inflater() { inflateEnd(&z); }
  } inflater;
  z_stream& z = inflater.z;
  if (inflateInit2(&z, 16 + MAX_WBITS) != Z_OK) throw std::runtime_error(path + ": zlib cannot start");
  std::string out;
  std::size_t fed = 0, checked = 0;
  int status = Z_OK;
  std::vector<char> buffer(kChunk);
  while (status != Z_STREAM_END) {  // each pass consumes input or makes output, or stops
    if (z.avail_in == 0 && fed < packed.size()) {
      const std::size_t n = std::min(packed.size() - fed, kFeed);
      z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(packed.data() + fed));
      z.avail_in = uInt(n);
      fed += n;
    }
    z.next_out = reinterpret_cast<Bytef*>(buffer.data());
    z.avail_out = uInt(buffer.size());
    status = inflate(&z, Z_NO_FLUSH);
    if (status != Z_OK && status != Z_STREAM_END) throw InputError(path + ": not a whole gzip file");
    out.append(buffer.data(), buffer.size() - z.avail_out);
    if (out.size() >= checked + (std::size_t(16) << 20) || status == Z_STREAM_END) {
      checked = out.size();
      if (out.size() > limit)
        throw InputError(path + ": unpacks to more than " + std::to_string(limit >> 20) + " MiB");
      check_memory_budget(double(out.size()) * parse_factor, path + ": unpacking it");
    }
  }
  return out;
}

}  // namespace heightmarch::cli
