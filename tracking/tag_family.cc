#include "tracking/tag_family.h"

#include <apriltag.h>
#include <common/image_u8.h>
#include <tag16h5.h>
#include <tag25h9.h>
#include <tag36h11.h>
#include <tagCircle21h7.h>
#include <tagCircle49h12.h>
#include <tagCustom48h12.h>
#include <tagStandard41h12.h>
#include <tagStandard52h13.h>

namespace ripple::tracking {

std::unique_ptr<TagFamily> TagFamily::Create(const std::string& name) {
  struct Entry {
    const char* name;
    apriltag_family_t* (*create)();
    void (*destroy)(apriltag_family_t*);
  };
  static const Entry kEntries[] = {
      {"tag36h11", tag36h11_create, tag36h11_destroy},
      {"tag25h9", tag25h9_create, tag25h9_destroy},
      {"tag16h5", tag16h5_create, tag16h5_destroy},
      {"tagCircle21h7", tagCircle21h7_create, tagCircle21h7_destroy},
      {"tagCircle49h12", tagCircle49h12_create, tagCircle49h12_destroy},
      {"tagStandard41h12", tagStandard41h12_create, tagStandard41h12_destroy},
      {"tagStandard52h13", tagStandard52h13_create, tagStandard52h13_destroy},
      {"tagCustom48h12", tagCustom48h12_create, tagCustom48h12_destroy},
  };
  for (const Entry& e : kEntries) {
    if (name == e.name)
      return std::unique_ptr<TagFamily>(
          new TagFamily(e.create(), name, e.destroy));
  }
  return nullptr;
}

TagFamily::~TagFamily() {
  if (family_) destroy_(family_);
}

int TagFamily::num_codes() const { return static_cast<int>(family_->ncodes); }
int TagFamily::width_at_border() const { return family_->width_at_border; }
int TagFamily::total_width() const { return family_->total_width; }

std::optional<TagBitmap> MakeTagBitmap(const TagFamily& family, int id) {
  if (id < 0 || id >= family.num_codes()) return std::nullopt;
  image_u8_t* im = apriltag_to_image(family.get(), id);
  TagBitmap bitmap;
  bitmap.total_width = im->width;
  bitmap.width_at_border = family.width_at_border();
  bitmap.cells.resize(size_t(im->width) * im->height);
  for (int r = 0; r < im->height; ++r)
    for (int c = 0; c < im->width; ++c)
      bitmap.cells[r * im->width + c] = im->buf[r * im->stride + c];
  image_u8_destroy(im);
  return bitmap;
}

}  // namespace ripple::tracking
