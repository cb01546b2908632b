// Integrity of a Matroska (.mkv) file, which the lossless recordings use:
// FFmpeg decodes a cut or corrupted FFV1 stream without complaint (the codec
// has no checksums in the version OpenCV writes), so we check the container
// ourselves. Matroska spec (IETF RFC 9559): EBML elements are an ID and a
// size, both variable-length integers; the Segment's size says where the
// file ends, and a CRC-32 element (ID 0xBF, IEEE polynomial, little-endian)
// as a master element's first child covers the rest of that element.
#ifndef RIPPLE_APP_APP_MATROSKA_H_
#define RIPPLE_APP_APP_MATROSKA_H_

#include <string>

namespace ripple::app {

// Empty when `path` is not Matroska (nothing to say), or when it is whole:
// its Segment ends within the file and every CRC-32 of the Segment's
// top-level elements matches. Otherwise what is wrong, e.g. "truncated
// (165903 of 174635 bytes)" or "corrupt (CRC-32 mismatch in the element at
// byte 523)".
std::string CheckMatroska(const std::string& path);

}  // namespace ripple::app

#endif  // RIPPLE_APP_APP_MATROSKA_H_
