// The light from the sun's position (--sun, --north): the apparent solar
// direction of render/sun.h in the tank frame, for a board whose +y axis
// points `north_deg` clockwise from true north.
#ifndef RIPPLE_APP_APP_SUN_H_
#define RIPPLE_APP_APP_SUN_H_

#include <Eigen/Core>
#include <string>

#include "render/sun.h"

namespace ripple::app {

// An East-North-Up vector in the tank frame (x, y on the board, z up).
// `north_deg`: the compass bearing of the tank's +y axis, clockwise from
// true north seen from above, so +y = (sin N, cos N, 0) in ENU and +x, a
// quarter turn clockwise from it, = (cos N, -sin N, 0). With N = 0, +y
// points north and +x east.
Eigen::Vector3d TankFromEnu(const render::EnuDirection& d, double north_deg);

// --sun LAT,LON,DATETIME (degrees north and east; an ISO 8601 date-time with
// its zone, render/sun.h's ParseIsoDateTime) as the unit vector towards the
// sun's apparent position in the tank frame (TankFromEnu) and the daylight
// for it and `sky` (render/sun.h, ComputeDaylight). Below the horizon the
// sun is off (daylight->sun_up false, ambient share 1) and `light` keeps its
// azimuth at 1 degree of elevation (it then casts nothing: the direct light
// is 0). False with `error` naming the option for malformed input, a place
// out of range or invalid sky options.
bool SunLightInTank(const std::string& text, double north_deg,
                    const render::SkyOptions& sky, Eigen::Vector3d* light,
                    render::Daylight* daylight, std::string* error);

}  // namespace ripple::app

#endif  // RIPPLE_APP_APP_SUN_H_
