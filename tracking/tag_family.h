// AprilTag families by name, and tag bitmaps as the family draws them. The
// only place that maps a rig's family string onto libapriltag.
#ifndef RIPPLE_TRACKING_TAG_FAMILY_H_
#define RIPPLE_TRACKING_TAG_FAMILY_H_

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

struct apriltag_family;

namespace ripple::tracking {

// Owns a libapriltag family; destroyed with the family's own destructor.
class TagFamily {
 public:
  // nullptr for a family libapriltag does not know.
  static std::unique_ptr<TagFamily> Create(const std::string& name);
  ~TagFamily();
  TagFamily(const TagFamily&) = delete;
  TagFamily& operator=(const TagFamily&) = delete;

  apriltag_family* get() const { return family_; }
  const std::string& name() const { return name_; }
  int num_codes() const;
  // Cells across the black square (the tag "edge" of DESIGN.md).
  int width_at_border() const;
  // Cells across the whole bitmap, white margin included.
  int total_width() const;

 private:
  TagFamily(apriltag_family* family, std::string name,
            void (*destroy)(apriltag_family*))
      : family_(family), name_(std::move(name)), destroy_(destroy) {}
  apriltag_family* family_;
  std::string name_;
  void (*destroy_)(apriltag_family*);
};

// A tag's cells, row-major, total_width x total_width, 0 = black, 255 =
// white, as the family draws it (row 0 at the top of the tag image).
struct TagBitmap {
  int total_width = 0;
  int width_at_border = 0;
  std::vector<uint8_t> cells;
  bool black(int row, int col) const {
    return cells[row * total_width + col] == 0;
  }
};

// nullopt when `id` is out of the family's range.
std::optional<TagBitmap> MakeTagBitmap(const TagFamily& family, int id);

}  // namespace ripple::tracking

#endif  // RIPPLE_TRACKING_TAG_FAMILY_H_
