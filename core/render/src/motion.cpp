// Motion blur: decomposed transforms, their interpolation, the shutter curve and the moving
// camera (conventions in facet/render/motion.h).
#include "facet/render/motion.h"

#include <algorithm>
#include <cmath>

namespace facet::render {

DecomposedTransform DecomposedTransform::decompose(const glm::dmat4& m) {
    DecomposedTransform d;
    d.translation = glm::dvec3(m[3]);
    const glm::dvec3 c0(m[0]), c1(m[1]), c2(m[2]);
    // Gram-Schmidt (modified): L = Q S, S upper triangular (s[col][row]).
    glm::dmat3 s(0.0);
    s[0][0] = glm::length(c0);
    const glm::dvec3 q0 = c0 / s[0][0];
    s[1][0] = glm::dot(q0, c1);
    const glm::dvec3 u1 = c1 - s[1][0] * q0;
    s[1][1] = glm::length(u1);
    const glm::dvec3 q1 = u1 / s[1][1];
    s[2][0] = glm::dot(q0, c2);
    glm::dvec3 u2 = c2 - s[2][0] * q0;
    s[2][1] = glm::dot(q1, u2);
    u2 -= s[2][1] * q1;
    s[2][2] = glm::length(u2);
    glm::dvec3 q2 = u2 / s[2][2];
    // A mirroring L: the sign goes into S so that Q is a rotation.
    if (glm::dot(glm::cross(q0, q1), q2) < 0.0) {
        q2 = -q2;
        s[2][2] = -s[2][2];
    }
    d.rotation = glm::normalize(glm::quat_cast(glm::dmat3(q0, q1, q2)));
    d.scale = s;
    return d;
}

glm::dmat4 DecomposedTransform::matrix() const {
    glm::dmat4 m(glm::mat3_cast(rotation) * scale);
    m[3] = glm::dvec4(translation, 1.0);
    return m;
}

glm::dmat4 interpolate_motion(std::span<const DecomposedTransform> steps, double tau) {
    if (steps.size() == 1) return steps[0].matrix();
    const double x = std::clamp(tau, 0.0, 1.0) * double(steps.size() - 1);
    const std::size_t i = std::min(std::size_t(x), steps.size() - 2);
    const double f = x - double(i);
    const DecomposedTransform& a = steps[i];
    const DecomposedTransform& b = steps[i + 1];
    DecomposedTransform d;
    d.translation = (1.0 - f) * a.translation + f * b.translation;
    // glm::slerp takes the shorter arc (q and -q are the same rotation).
    d.rotation = glm::slerp(a.rotation, b.rotation, f);
    for (int c = 0; c < 3; ++c) d.scale[c] = (1.0 - f) * a.scale[c] + f * b.scale[c];
    return d.matrix();
}

ShutterCurve::ShutterCurve(std::span<const double> weights) {
    const std::size_t n = weights.size();
    if (n == 0) return;
    double total = 0.0;
    for (double w : weights) total += w;
    m_pdf.resize(n);
    m_cdf.resize(n + 1);
    m_cdf[0] = 0.f;
    double acc = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        // Density per unit tau: the cell's share of the total over its width 1/n.
        m_pdf[i] = float(weights[i] / total * double(n));
        acc += weights[i];
        m_cdf[i + 1] = float(acc / total);
    }
    m_cdf[n] = 1.f;
}

float ShutterCurve::sample(float u) const {
    if (m_cdf.empty()) return u;
    const std::size_t n = m_pdf.size();
    // The cell i with cdf[i] <= u < cdf[i + 1] (never an empty cell: its interval is empty).
    const auto it = std::upper_bound(m_cdf.begin() + 1, m_cdf.end(), u);
    const std::size_t i = std::min(std::size_t(it - m_cdf.begin()) - 1, n - 1);
    const float width = m_cdf[i + 1] - m_cdf[i];
    const float f = width > 0.f ? (u - m_cdf[i]) / width : 0.f;
    const float tau = (float(i) + std::clamp(f, 0.f, 1.f)) / float(n);
    return std::min(tau, 0x1.fffffep-1f);  // in [0, 1)
}

float ShutterCurve::pdf(float tau) const {
    if (!(tau >= 0.f && tau < 1.f)) return 0.f;
    if (m_pdf.empty()) return 1.f;
    const std::size_t i = std::min(std::size_t(tau * float(m_pdf.size())), m_pdf.size() - 1);
    return m_pdf[i];
}

Camera CameraMotion::at(float tau) const {
    if (steps.size() < 2) return steps.empty() ? Camera{} : steps[0];
    const double x = std::clamp(double(tau), 0.0, 1.0) * double(steps.size() - 1);
    const std::size_t i = std::min(std::size_t(x), steps.size() - 2);
    const double f = x - double(i);
    const Camera& a = steps[i];
    const Camera& b = steps[i + 1];
    auto orientation = [](const Camera& c) {
        return glm::quat_cast(
            glm::dmat3(glm::dvec3(c.right), glm::dvec3(c.true_up), -glm::dvec3(c.forward)));
    };
    const glm::dmat3 r = glm::mat3_cast(glm::slerp(orientation(a), orientation(b), f));
    Camera c = steps[0];
    c.position = Vec3((1.0 - f) * glm::dvec3(a.position) + f * glm::dvec3(b.position));
    c.right = Vec3(glm::normalize(r[0]));
    c.true_up = Vec3(glm::normalize(r[1]));
    c.forward = Vec3(-glm::normalize(r[2]));
    c.look_at = c.position + c.forward;
    c.up = c.true_up;
    return c;
}

}  // namespace facet::render
