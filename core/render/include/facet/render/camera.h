// The perspective pinhole camera of the renderer.
//
// Conventions (these are the scene format's; POV-Ray and Blender exports must match them):
//  - World space is right-handed. The camera sits at `position` and looks at `look_at`;
//    forward f = normalize(look_at - position), right r = normalize(cross(f, up)),
//    true up u = cross(r, f). `up` only needs to be non-parallel to f.
//  - `fov_y_deg` is the FULL vertical field of view in degrees: the angle between the rays
//    through the top edge and the bottom edge of the image (not through pixel centres).
//    The horizontal field of view follows from the aspect ratio:
//      tan(fov_x / 2) = (width / height) * tan(fov_y / 2)
//    (POV-Ray's `angle` is this fov_x; Blender's camera with sensor_fit = VERTICAL has
//    angle_y = fov_y.) Pixels are square.
//  - Film coordinates are in pixels: (0, 0) is the top-left corner of the image, x grows to the
//    right, y grows downward; pixel (i, j) covers [i, i+1) x [j, j+1) and its centre is
//    (i + 0.5, j + 0.5). The ray through film position (x, y) has direction
//      d = normalize(f + s_x r + s_y u),
//      s_x = (2 x / width - 1) tan(fov_x / 2),   s_y = (1 - 2 y / height) tan(fov_y / 2).
//  - Rays start exactly at `position` (no near plane) and have unit direction.
#pragma once

#include <optional>

#include "facet/types.h"

namespace facet::render {

// A ray o + t d, t in (0, tmax]. d is a unit vector.
struct Ray {
    Vec3 o{0.f};
    Vec3 d{0.f, 0.f, 1.f};
    float tmax = kInfinity;
};

struct Camera {
    Vec3 position{0.f};
    Vec3 look_at{0.f, 0.f, -1.f};
    Vec3 up{0.f, 1.f, 0.f};
    float fov_y_deg = 40.f;
    int width = 0;
    int height = 0;

    // Orthonormal camera basis and half-extents of the image plane at distance 1; filled by
    // make(). Do not set by hand.
    Vec3 forward{0.f, 0.f, -1.f}, right{1.f, 0.f, 0.f}, true_up{0.f, 1.f, 0.f};
    float tan_half_x = 0.f, tan_half_y = 0.f;

    // Builds a camera and its basis. Preconditions (validated by the scene loader, which names
    // the JSON path on failure): position != look_at, up not parallel to the view direction,
    // 0 < fov_y_deg < 180, width and height >= 1.
    static Camera make(const Vec3& position, const Vec3& look_at, const Vec3& up, float fov_y_deg,
                       int width, int height);

    // The primary ray through film position `film_pos` (pixels, see conventions above).
    Ray generate_ray(Vec2 film_pos) const;

    // Film position (pixels) where world point p projects, or nullopt when p is not in front of
    // the camera. The inverse of generate_ray (for tests and exporters).
    std::optional<Vec2> project(const Vec3& p) const;
};

// Inline: runs for every camera sample.
inline Ray Camera::generate_ray(Vec2 film_pos) const {
    // Image-plane coordinates at distance 1: x in [-tan_half_x, tan_half_x] from left to right,
    // y in [-tan_half_y, tan_half_y] from bottom to top (film y grows downward).
    float sx = (2.f * film_pos.x / float(width) - 1.f) * tan_half_x;
    float sy = (1.f - 2.f * film_pos.y / float(height)) * tan_half_y;
    Ray ray;
    ray.o = position;
    ray.d = glm::normalize(forward + sx * right + sy * true_up);
    ray.tmax = kInfinity;
    return ray;
}

}  // namespace facet::render
