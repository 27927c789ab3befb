// Perspective pinhole camera (conventions in facet/render/camera.h).
#include "facet/render/camera.h"

namespace facet::render {

Camera Camera::make(const Vec3& position, const Vec3& look_at, const Vec3& up, float fov_y_deg,
                    int width, int height) {
    Camera c;
    c.position = position;
    c.look_at = look_at;
    c.up = up;
    c.fov_y_deg = fov_y_deg;
    c.width = width;
    c.height = height;
    // Basis in double: look-at targets far away (or tiny fovs) lose nothing to float here.
    glm::dvec3 f = glm::normalize(glm::dvec3(look_at) - glm::dvec3(position));
    glm::dvec3 r = glm::normalize(glm::cross(f, glm::dvec3(up)));
    glm::dvec3 u = glm::cross(r, f);
    c.forward = Vec3(f);
    c.right = Vec3(r);
    c.true_up = Vec3(u);
    double tan_y = std::tan(0.5 * double(fov_y_deg) * kPiD / 180.0);
    c.tan_half_y = float(tan_y);
    c.tan_half_x = float(tan_y * double(width) / double(height));
    return c;
}

std::optional<Vec2> Camera::project(const Vec3& p) const {
    Vec3 v = p - position;
    float z = glm::dot(v, forward);
    if (!(z > 0.f)) return std::nullopt;
    float sx = glm::dot(v, right) / z;
    float sy = glm::dot(v, true_up) / z;
    float x = 0.5f * (sx / tan_half_x + 1.f) * float(width);
    float y = 0.5f * (1.f - sy / tan_half_y) * float(height);
    return Vec2(x, y);
}

}  // namespace facet::render
