#include "app/app_matroska.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <vector>

namespace ripple::app {
namespace {

constexpr uint32_t kEbmlId = 0x1A45DFA3;
constexpr uint32_t kSegmentId = 0x18538067;
constexpr uint32_t kCrc32Id = 0xBF;

// CRC-32 (IEEE 802.3, reflected polynomial 0xEDB88320), as zlib computes it.
uint32_t Crc32Update(uint32_t crc, const unsigned char* data, size_t n) {
  static const std::array<uint32_t, 256> table = [] {
    std::array<uint32_t, 256> t{};
    for (uint32_t i = 0; i < 256; ++i) {
      uint32_t c = i;
      for (int k = 0; k < 8; ++k) c = (c & 1) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
      t[i] = c;
    }
    return t;
  }();
  crc = ~crc;
  for (size_t i = 0; i < n; ++i)
    crc = table[(crc ^ data[i]) & 0xFF] ^ (crc >> 8);
  return ~crc;
}

class Reader {
 public:
  explicit Reader(FILE* f) : f_(f) {}
  bool Byte(int* b) {
    const int c = std::fgetc(f_);
    if (c == EOF) return false;
    ++pos_;
    *b = c;
    return true;
  }
  // An EBML variable-length integer; `keep_marker` for IDs. `unknown` is
  // set for a size of all ones (size not known when written).
  bool Vint(bool keep_marker, uint64_t* value, bool* unknown = nullptr) {
    int first;
    if (!Byte(&first) || first == 0) return false;
    int len = 1;
    while (!(first & (0x80 >> (len - 1)))) ++len;
    uint64_t v = keep_marker ? first : first & (0xFF >> len);
    bool ones = (first & (0xFF >> len)) == (0xFF >> len);
    for (int i = 1; i < len; ++i) {
      int b;
      if (!Byte(&b)) return false;
      v = (v << 8) | b;
      ones = ones && b == 0xFF;
    }
    if (unknown) *unknown = !keep_marker && ones;
    *value = v;
    return true;
  }
  bool Read(unsigned char* out, size_t n) {
    const size_t got = std::fread(out, 1, n, f_);
    pos_ += got;
    return got == n;
  }
  bool Seek(uint64_t pos) {
    if (std::fseek(f_, static_cast<long>(pos), SEEK_SET) != 0) return false;
    pos_ = pos;
    return true;
  }
  uint64_t pos() const { return pos_; }

 private:
  FILE* f_;
  uint64_t pos_ = 0;
};

}  // namespace

std::string CheckMatroska(const std::string& path) {
  std::unique_ptr<FILE, int (*)(FILE*)> file(std::fopen(path.c_str(), "rb"),
                                             std::fclose);
  if (!file) return "";
  std::fseek(file.get(), 0, SEEK_END);
  const long end = std::ftell(file.get());
  if (end <= 0) return "";
  const uint64_t file_bytes = static_cast<uint64_t>(end);
  Reader r(file.get());
  r.Seek(0);
  uint64_t id = 0, size = 0;
  bool unknown = false;
  if (!r.Vint(true, &id) || id != kEbmlId) return "";  // not Matroska
  const std::string cut = "truncated (" + std::to_string(file_bytes) + " bytes";
  if (!r.Vint(false, &size, &unknown) || unknown ||
      r.pos() + size > file_bytes || !r.Seek(r.pos() + size))
    return cut + ", the header is incomplete)";
  if (!r.Vint(true, &id) || id != kSegmentId)
    return "corrupt (no Segment after the EBML header)";
  if (!r.Vint(false, &size, &unknown)) return cut + ")";
  if (unknown) return "";  // a live stream's size is never written
  const uint64_t segment_end = r.pos() + size;
  if (segment_end > file_bytes)
    return "truncated (" + std::to_string(file_bytes) + " of " +
           std::to_string(segment_end) + " bytes)";
  std::vector<unsigned char> buffer(1 << 20);
  while (r.pos() < segment_end) {
    const uint64_t element = r.pos();
    bool child_unknown = false;
    if (!r.Vint(true, &id) || !r.Vint(false, &size, &child_unknown))
      return "corrupt (unreadable element at byte " + std::to_string(element) +
             ")";
    if (child_unknown) return "";  // cannot be checked further
    const uint64_t data = r.pos();
    if (data + size > segment_end)
      return "corrupt (the element at byte " + std::to_string(element) +
             " overruns the Segment)";
    // A CRC-32 element first: check the rest of this element against it.
    uint64_t crc_id = 0, crc_size = 0;
    const bool is_master_with_crc = size >= 6 && r.Vint(true, &crc_id) &&
                                    crc_id == kCrc32Id &&
                                    r.Vint(false, &crc_size) && crc_size == 4;
    if (is_master_with_crc) {
      unsigned char stored[4];
      if (!r.Read(stored, 4)) return cut + ")";
      const uint32_t want = stored[0] | stored[1] << 8 | stored[2] << 16 |
                            static_cast<uint32_t>(stored[3]) << 24;
      uint32_t crc = 0;
      uint64_t left = data + size - r.pos();
      while (left > 0) {
        const size_t n =
            static_cast<size_t>(std::min<uint64_t>(left, buffer.size()));
        if (!r.Read(buffer.data(), n)) return cut + ")";
        crc = Crc32Update(crc, buffer.data(), n);
        left -= n;
      }
      if (crc != want)
        return "corrupt (CRC-32 mismatch in the element at byte " +
               std::to_string(element) + ")";
    }
    if (!r.Seek(data + size)) return cut + ")";
  }
  return "";
}

}  // namespace ripple::app
