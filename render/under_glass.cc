#include "render/under_glass.h"

#include <vector>

#include "render/tank_paths.h"

namespace ripple::render::internal {

UnderGlassView TraceUnderGlassView(const TankGeometry& tank,
                                   const WaterOptics& optics, int side) {
  const PathTank t = MakePathTank(tank, optics);
  UnderGlassView view;
  view.traced = true;
  if (!(t.A > t.a) || !(t.B > t.b) || side < 1) {
    // No glass: the board at the walls' foot sees the sky as the open board.
    for (int w = 0; w < 4; ++w) view.sky[w] = glm::vec3(1.0f);
    return view;
  }
  const double n = static_cast<double>(side) * side;
  const std::vector<glm::dvec3> dirs = CosineDirections(side);
  for (const int axis : {0, 1}) {
    glm::dvec3 p(0.0, 0.0, 1e-7);
    p[axis] = axis == 0 ? 0.5 * (t.a + t.A) : 0.5 * (t.b + t.B);
    PathEndSums sums;
    for (const glm::dvec3& d : dirs)
      TracePath(t, p, d, PathMedium::kGlass, glm::dvec3(1.0), sums);
    for (const int w : {2 * axis, 2 * axis + 1}) {
      view.sky[w] = glm::vec3(sums.sky / n);
      view.board[w] = static_cast<float>(sums.board / n);
      view.floor[w] = static_cast<float>(sums.floor / n);
      view.under[w] = static_cast<float>(sums.under_glass / n);
    }
  }
  return view;
}

}  // namespace ripple::render::internal
