// Perspective and orthographic cameras with lens shift and a thin lens (conventions in
// facet/render/camera.h).
#include "facet/render/camera.h"

#include "facet/frame.h"
#include "facet/sampling.h"

namespace facet::render {

Camera Camera::make(const Vec3& position, const Vec3& look_at, const Vec3& up, float fov_y_deg,
                    int width, int height, const CameraOptions& o) {
    Camera c;
    c.position = position;
    c.look_at = look_at;
    c.up = up;
    c.fov_y_deg = fov_y_deg;
    c.width = width;
    c.height = height;
    c.projection = o.projection;
    // Basis in double: look-at targets far away (or tiny fovs) lose nothing to float here.
    glm::dvec3 f = glm::normalize(glm::dvec3(look_at) - glm::dvec3(position));
    glm::dvec3 r = glm::normalize(glm::cross(f, glm::dvec3(up)));
    glm::dvec3 u = glm::cross(r, f);
    c.forward = Vec3(f);
    c.right = Vec3(r);
    c.true_up = Vec3(u);
    const double aspect = double(width) / double(height);
    if (o.projection == Projection::Perspective) {
        double tan_y = std::tan(0.5 * double(fov_y_deg) * kPiD / 180.0);
        c.tan_half_y = float(tan_y);
        c.tan_half_x = float(tan_y * aspect);
    } else {
        // Blender's Ortho Scale is the extent of the larger image side (sensor fit AUTO).
        const double half = 0.5 * double(o.ortho_scale);
        c.tan_half_x = float(width >= height ? half : half * aspect);
        c.tan_half_y = float(width >= height ? half / aspect : half);
    }
    // Shift: fractions of the full extent of the larger side, 2 max(h_x, h_y).
    const double larger = 2.0 * std::max(double(c.tan_half_x), double(c.tan_half_y));
    c.center_x = float(larger * double(o.shift_x));
    c.center_y = float(larger * double(o.shift_y));
    if (o.aperture_radius > 0.f) {
        c.lens_radius = o.aperture_radius;
        c.focus_distance = o.focus_distance;
        c.blades = o.blades;
        c.blade_rotation = float(double(o.rotation_deg) * kPiD / 180.0);
    }
    return c;
}

Vec2 Camera::sample_aperture(Vec2 u) const {
    const Vec2 p = blades == 0 ? sample_uniform_disk_concentric(u)
                               : sample_regular_polygon(u, blades, blade_rotation);
    return lens_radius * p;
}

namespace {

// Where ray (o, e) (e not necessarily unit) meets the plane through p with normal n, minus p.
// A ray parallel to the plane (grazing) gets a huge but finite offset: the texture then reads
// its coarsest level, which is what a grazing footprint covers.
Vec3 plane_offset(const Vec3& o, const Vec3& e, const Vec3& p, const Vec3& n) {
    constexpr float kMinCos = 1e-6f;  // |dot(e, n)| below this counts as grazing
    float den = glm::dot(e, n);
    if (!(std::fabs(den) > kMinCos)) den = std::copysign(kMinCos, den);
    return o + (glm::dot(p - o, n) / den) * e - p;
}

}  // namespace

PixelFootprint Camera::footprint(const Vec3& o, const Vec3& d, const Vec3& p, const Vec3& n) const {
    const Vec3 wx = (2.f * tan_half_x / float(width)) * right;
    const Vec3 wy = (-2.f * tan_half_y / float(height)) * true_up;
    if (projection == Projection::Orthographic)
        return {plane_offset(o + wx, d, p, n), plane_offset(o + wy, d, p, n)};
    const Vec3 e = d / glm::dot(d, forward);
    return {plane_offset(o, e + wx, p, n), plane_offset(o, e + wy, p, n)};
}

PixelFootprint Camera::footprint_at(const Vec3& p, const Vec3& n) const {
    const Vec3 v = p - position;
    if (projection == Projection::Orthographic)
        return footprint(p - glm::dot(v, forward) * forward, forward, p, n);
    const float len = glm::length(v);
    if (!(len > 0.f)) return {};
    const Vec3 d = v / len;
    // In front of the camera (within ~84 degrees of the view axis): the lens-centre ray.
    constexpr float kMinForward = 0.1f;
    if (glm::dot(d, forward) > kMinForward) return footprint(position, d, p, n);
    // Behind or beside it: the centre pixel's angular steps, about the direction to p.
    const Frame fr = Frame::from_z(d);
    const float sx = 2.f * tan_half_x / float(width), sy = 2.f * tan_half_y / float(height);
    return {plane_offset(position, d + sx * fr.x, p, n),
            plane_offset(position, d + sy * fr.y, p, n)};
}

std::optional<Vec2> Camera::project(const Vec3& p) const {
    Vec3 v = p - position;
    float z = glm::dot(v, forward);
    if (!(z > 0.f)) return std::nullopt;
    float sx = glm::dot(v, right), sy = glm::dot(v, true_up);
    if (projection == Projection::Perspective) {
        sx /= z;
        sy /= z;
    }
    float x = 0.5f * ((sx - center_x) / tan_half_x + 1.f) * float(width);
    float y = 0.5f * (1.f - (sy - center_y) / tan_half_y) * float(height);
    return Vec2(x, y);
}

std::optional<Vec2> Camera::project(const Vec3& p, Vec2 u_lens) const {
    if (!has_lens()) return project(p);
    Vec3 v = p - position;
    float z = glm::dot(v, forward);
    if (!(z > 0.f)) return std::nullopt;
    // The ray from lens point l through p crosses the plane of focus at q; the lens-centre ray
    // through q starts at the same film position (generate_ray aims every lens point of a film
    // position at one point of that plane).
    const Vec2 l = sample_aperture(u_lens);
    const Vec2 pxy(glm::dot(v, right), glm::dot(v, true_up));
    // Perspective: the line from l (depth 0) through q (depth focus_distance) meets p at depth
    // z when q = l + (p - l) focus_distance / z. Orthographic: the lens-centre ray starts at q
    // and the lens point is q + l, so p = q + l (1 - z / focus_distance).
    const Vec2 q = projection == Projection::Perspective ? l + (pxy - l) * (focus_distance / z)
                                                         : pxy - l * (1.f - z / focus_distance);
    return project(position + q.x * right + q.y * true_up + focus_distance * forward);
}

Vec3 Camera::window_point(const Vec3& c) const {
    float sx = c.x, sy = c.y;
    if (projection == Projection::Perspective) {
        if (c.z == 0.f) return Vec3(0.f);
        sx /= c.z;
        sy /= c.z;
    }
    return {0.5f * ((sx - center_x) / tan_half_x + 1.f),
            0.5f * ((sy - center_y) / tan_half_y + 1.f), 0.f};
}

}  // namespace facet::render
