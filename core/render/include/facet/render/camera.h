// The camera of the renderer: perspective or orthographic, with lens shift and an optional thin
// lens (depth of field) with a round or polygonal aperture, as Blender/Cycles define them.
//
// Conventions (these are the scene format's, scenes/FORMAT.md "camera"; POV-Ray and Blender
// exports must match them):
//  - World space is right-handed. The camera sits at `position` and looks at `look_at`;
//    forward f = normalize(look_at - position), right r = normalize(cross(f, up)),
//    true up u = cross(r, f). `up` only needs to be non-parallel to f.
//  - Film coordinates are in pixels: (0, 0) is the top-left corner of the image, x grows to the
//    right, y grows downward; pixel (i, j) covers [i, i+1) x [j, j+1) and its centre is
//    (i + 0.5, j + 0.5). Pixels are square.
//  - The image window: film position (x, y) maps to window coordinates
//      s_x = c_x + (2 x / width - 1) h_x,   s_y = c_y + (1 - 2 y / height) h_y
//    (h = half-extents, c = the lens-shift offset of the window centre).
//    Perspective: the window lies on the plane at distance 1 in front of `position`;
//      h_y = tan(fov_y / 2), h_x = (width / height) h_y, where `fov_y_deg` is the FULL vertical
//      field of view (rays through the top and bottom edges, not pixel centres). POV-Ray's
//      `angle` is fov_x = 2 atan(h_x); Blender's camera with sensor_fit = VERTICAL has
//      angle_y = fov_y. Lens-centre ray: origin `position`, direction
//      normalize(f + s_x r + s_y u).
//    Orthographic: the window lies in the plane through `position` perpendicular to f, in scene
//      units; the larger image side spans `ortho_scale` (Blender's Ortho Scale under sensor fit
//      AUTO): h = ortho_scale / 2 on the larger side, h = (ortho_scale / 2) (smaller / larger)
//      on the other. Lens-centre ray: origin position + s_x r + s_y u, direction f.
//    Lens shift (Blender's shift_x / shift_y, sensor fit AUTO): the window moves by the shift
//      times the FULL extent of the larger image side, c = 2 max(h_x, h_y) (shift_x, shift_y),
//      for both projections (Cycles, blender/camera.cpp: viewplane offset 2 aspectratio shift).
//  - Thin lens (aperture_radius > 0; Cycles' model): the lens is the disc (blades = 0) or the
//    regular polygon with `blades` corners on the circle of radius aperture_radius (scene
//    units) in the plane through `position` perpendicular to f (orthographic: through the
//    lens-centre ray's origin); polygon edge midpoints lie at angles rotation + 2 pi k / blades
//    from r toward u, corners half-way between. The lens sample u in [0,1)^2 maps uniformly
//    onto that area (sample_aperture). The ray from lens point o + l_x r + l_y u goes to the
//    point where the lens-centre ray crosses the plane of focus, at distance focus_distance
//    along f (a plane, not a sphere). aperture_radius = 0 is the pinhole: no lens sample is
//    drawn and rays are exactly the lens-centre rays.
//  - Rays start exactly at their origin (no near plane) and have unit direction.
//  - Pixel footprints (ray differentials, pbrt-v4 sections 5.1 and 10.1.1): the rays of the
//    film positions one pixel to the right (x + 1) and one pixel down (y + 1), with the SAME
//    lens sample, meet the tangent plane of a hit at p + dpdx and p + dpdy. In closed form, with
//    the window's pixel steps w_x = (2 h_x / width) r and w_y = -(2 h_y / height) u:
//      perspective (pinhole and thin lens alike): the differential ray leaves the same origin o
//        with direction d / dot(d, f) + w (the focus point moves by focus_distance w, and the
//        lens point stays);
//      orthographic (with or without lens): the differential ray leaves o + w in direction d.
//    Exact for camera rays. At later path vertices (pbrt-v4's Camera::Approximate_dp_dxy) the
//    footprint is that of the lens-centre camera ray through p, as if p were seen directly:
//    exact for pinhole and orthographic cameras at points the camera sees, approximate for a
//    thin lens (its footprint at the plane of focus) and for points behind the camera (there
//    the centre pixel's angular step about the direction to p).
#pragma once

#include <cmath>
#include <cstdint>
#include <optional>

#include "facet/types.h"

namespace facet::render {

// A ray o + t d, t in (0, tmax]. d is a unit vector. Its shutter time (motion blur,
// facet/render/motion.h) travels beside it: RayPacket::time, and the `time` argument of the
// scene's single-ray queries for scenes that move; a Ray alone is traced at time 0, so the
// rays of scenes that do not move are exactly what they were before motion blur existed.
struct Ray {
    Vec3 o{0.f};
    Vec3 d{0.f, 0.f, 1.f};
    float tmax = kInfinity;
};

enum class Projection : std::uint8_t { Perspective, Orthographic };

// The pixel footprint on a surface: p + dpdx, p + dpdy are where the differential rays meet
// the tangent plane at p (conventions).
struct PixelFootprint {
    Vec3 dpdx{0.f}, dpdy{0.f};
};

// What a camera has besides the pinhole perspective's position, orientation, fov and size;
// the defaults are the pinhole perspective camera.
struct CameraOptions {
    Projection projection = Projection::Perspective;
    float ortho_scale = 1.f;             // orthographic: extent of the larger image side
    float shift_x = 0.f, shift_y = 0.f;  // fractions of the larger image side
    float aperture_radius = 0.f;         // scene units; 0 = pinhole
    float focus_distance = 1.f;          // along f, > 0 (read only when aperture_radius > 0)
    int blades = 0;                      // 0 = round aperture, else >= 3
    float rotation_deg = 0.f;            // polygon rotation, degrees from r toward u
};

struct Camera {
    Vec3 position{0.f};
    Vec3 look_at{0.f, 0.f, -1.f};
    Vec3 up{0.f, 1.f, 0.f};
    float fov_y_deg = 40.f;
    int width = 0;
    int height = 0;
    Projection projection = Projection::Perspective;

    // Orthonormal camera basis, the image window's half-extents (tan_half_*: perspective, on
    // the plane at distance 1; orthographic, in scene units) and centre (lens shift), and the
    // thin lens; filled by make(). Do not set by hand.
    Vec3 forward{0.f, 0.f, -1.f}, right{1.f, 0.f, 0.f}, true_up{0.f, 1.f, 0.f};
    float tan_half_x = 0.f, tan_half_y = 0.f;
    float center_x = 0.f, center_y = 0.f;
    float lens_radius = 0.f, focus_distance = 1.f;
    int blades = 0;
    float blade_rotation = 0.f;  // radians

    // Builds a camera and its basis. Preconditions (validated by the scene loader, which names
    // the JSON path on failure): position != look_at, up not parallel to the view direction,
    // 0 < fov_y_deg < 180, width and height >= 1, ortho_scale > 0, finite shifts,
    // aperture_radius >= 0, focus_distance > 0 when aperture_radius > 0, blades 0 or >= 3.
    static Camera make(const Vec3& position, const Vec3& look_at, const Vec3& up, float fov_y_deg,
                       int width, int height, const CameraOptions& options = {});

    // True when rays need a lens sample (aperture_radius > 0).
    bool has_lens() const { return lens_radius > 0.f; }

    // The lens-centre ray through film position `film_pos` (pixels, see conventions above):
    // the pinhole's ray, and the whole camera when !has_lens().
    Ray generate_ray(Vec2 film_pos) const;
    // The ray through film position `film_pos` from the lens point of sample `u_lens` in
    // [0,1)^2 (a random-number argument; ignored without a lens).
    Ray generate_ray(Vec2 film_pos, Vec2 u_lens) const;

    // Window coordinates of film positions (conventions) and the perspective lens-centre
    // direction, normalize(f + s_x r + s_y u) as glm::normalize computes it (v times
    // 1 / sqrt(dot(v, v))). Written once for generate_ray (T = float) and for packets of
    // camera rays (T a GCC vector of floats, `sqrt` its square root): the same operations lane
    // by lane, so every lane gets generate_ray's bits.
    template <class T>
    T window_x(T film_x) const {
        return (2.f * film_x / float(width) - 1.f) * tan_half_x + center_x;
    }
    template <class T>
    T window_y(T film_y) const {
        return (1.f - 2.f * film_y / float(height)) * tan_half_y + center_y;
    }
    template <class T, class Sqrt>
    void perspective_direction(T sx, T sy, T& dx, T& dy, T& dz, Sqrt sqrt) const {
        dx = forward.x + sx * right.x + sy * true_up.x;
        dy = forward.y + sx * right.y + sy * true_up.y;
        dz = forward.z + sx * right.z + sy * true_up.z;
        const T inv = 1.f / sqrt(dx * dx + dy * dy + dz * dz);
        dx *= inv;
        dy *= inv;
        dz *= inv;
    }

    // The lens point (r, u coordinates, scene units) of lens sample u: uniform on the aperture.
    Vec2 sample_aperture(Vec2 u) const;

    // The footprint at hit point p (unit normal n) of camera ray (o, d): exact (conventions).
    PixelFootprint footprint(const Vec3& o, const Vec3& d, const Vec3& p, const Vec3& n) const;
    // The footprint at p as if seen from the lens centre: for later path vertices
    // (conventions).
    PixelFootprint footprint_at(const Vec3& p, const Vec3& n) const;

    // Film position (pixels) where world point p projects through the lens centre, or nullopt
    // when p is not in front of the camera (the lens plane). The inverse of generate_ray(film)
    // (for tests and exporters).
    std::optional<Vec2> project(const Vec3& p) const;
    // Film position from which the ray of lens sample u_lens passes through p: the inverse of
    // generate_ray(film, u_lens). Over all u_lens, the image of a point (its circle of
    // confusion); a point on the plane of focus projects to one film position for every u.
    std::optional<Vec2> project(const Vec3& p, Vec2 u_lens) const;
    // World point p in camera space: (dot(v, r), dot(v, u), dot(v, f)), v = p - position
    // (Cycles' camera space: z forward).
    Vec3 camera_point(const Vec3& p) const {
        const Vec3 v = p - position;
        return {glm::dot(v, right), glm::dot(v, true_up), glm::dot(v, forward)};
    }
    // Camera-space point c on the image as Cycles' normalized device coordinates (its Window
    // texture coordinates): (x, y, 0), x from 0 at the left edge to 1 at the right, y from 0 at
    // the bottom to 1 at the top, lens shift included. Perspective: through the lens centre,
    // dividing by c.z whatever its sign (points behind the camera land mirrored, as in Cycles'
    // projective transform; c.z = 0 gives 0).
    Vec3 window_point(const Vec3& c) const;
};

// Inline: runs for every camera sample.
inline Ray Camera::generate_ray(Vec2 film_pos) const {
    // Window coordinates: x from left to right, y from bottom to top (film y grows downward).
    // The centre offsets are 0 without lens shift, which leaves every value unchanged.
    const float sx = window_x(film_pos.x);
    const float sy = window_y(film_pos.y);
    Ray ray;
    if (projection == Projection::Perspective) {
        ray.o = position;
        perspective_direction(sx, sy, ray.d.x, ray.d.y, ray.d.z,
                              [](float v) { return std::sqrt(v); });
    } else {
        ray.o = position + sx * right + sy * true_up;
        ray.d = forward;
    }
    ray.tmax = kInfinity;
    return ray;
}

inline Ray Camera::generate_ray(Vec2 film_pos, Vec2 u_lens) const {
    Ray ray = generate_ray(film_pos);
    if (!has_lens()) return ray;
    // Where the lens-centre ray crosses the plane of focus (dot(d, f) > 0 for every window
    // position of a perspective camera with fov < 180 degrees, and 1 for orthographic).
    const Vec3 focus = ray.o + (focus_distance / glm::dot(ray.d, forward)) * ray.d;
    const Vec2 l = sample_aperture(u_lens);
    ray.o += l.x * right + l.y * true_up;
    ray.d = glm::normalize(focus - ray.o);
    return ray;
}

}  // namespace facet::render
