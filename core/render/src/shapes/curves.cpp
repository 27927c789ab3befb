// Shape kind "curves": strands of round tubes or flat ribbons along linear, uniform cubic
// B-spline or Catmull-Rom curves with a radius per control point (hair, fur, grass), traced as
// Embree curve geometry (embree_scene.cpp). Hits: scene.h, "Curves".
#include <glm/gtc/matrix_transform.hpp>

#include <cmath>

#include "../io/pov_writer.h"
#include "../kind_build.h"
#include "../textures/cycles_noise.h"

namespace facet::render {

namespace {

struct BasisInfo {
    CurveGeom::Basis basis;
    const char* name;
    const char* pov;      // POV-Ray's sphere_sweep spline of the same curve
    unsigned min_points;  // control points of one segment
};

constexpr BasisInfo kBases[] = {{CurveGeom::Basis::Linear, "linear", "linear_spline", 2},
                                {CurveGeom::Basis::BSpline, "bspline", "b_spline", 4},
                                {CurveGeom::Basis::CatmullRom, "catmull_rom", "cubic_spline", 4}};

const BasisInfo* find_basis(const std::string& name) {
    for (const BasisInfo& b : kBases)
        if (name == b.name) return &b;
    return nullptr;
}

// The checked strands of a curves shape: its basis, profile, points and radii (object space)
// and each strand's first control point and count. Errors name the JSON pointer through
// `checks`.
struct Strands {
    const BasisInfo* basis = nullptr;
    bool flat = false;
    std::vector<std::uint32_t> first, count;
};

Strands check_strands(const ShapeDesc& s, const std::string& ptr, const BuildChecks& checks) {
    Strands out;
    out.basis = find_basis(s.basis);
    if (!out.basis)
        checks.fail(ptr + "/basis", "unknown curve basis '" + s.basis +
                                        "' (expected linear, bspline or catmull_rom)");
    if (s.profile == "flat")
        out.flat = true;
    else if (!s.profile.empty() && s.profile != "round")
        checks.fail(ptr + "/profile",
                    "unknown curve profile '" + s.profile + "' (expected round or flat)");
    const CurveData& c = s.curves;
    if (c.points.empty() || c.points.size() % 3 != 0)
        checks.fail(ptr + "/points",
                    "expected a flat array of 3n numbers (x0, y0, z0, x1, ...), got " +
                        std::to_string(c.points.size()) + " numbers");
    for (std::size_t i = 0; i < c.points.size(); ++i)
        if (!std::isfinite(c.points[i]))
            checks.fail(ptr + "/points/" + std::to_string(i), "must be a finite number");
    const std::size_t n = c.num_points();
    if (c.radius.size() != 1 && c.radius.size() != n)
        checks.fail(ptr + "/radius", "expected a number or one radius per point (" +
                                         std::to_string(n) + "), got an array of " +
                                         std::to_string(c.radius.size()));
    for (std::size_t i = 0; i < c.radius.size(); ++i) {
        const std::string rp =
            ptr + "/radius" + (c.radius.size() == 1 ? "" : "/" + std::to_string(i));
        if (!std::isfinite(c.radius[i])) checks.fail(rp, "must be a finite number");
        if (!(c.radius[i] > 0.f)) checks.fail(rp, "must be > 0");
    }
    const unsigned need = out.basis->min_points;
    auto need_text = [&](std::uint64_t got) {
        return "a " + std::string(out.basis->name) + " strand needs at least " +
               std::to_string(need) + " control points (one segment), got " + std::to_string(got);
    };
    if (c.counts.empty()) {
        if (n < need) checks.fail(ptr + "/points", need_text(n));
        out.first = {0};
        out.count = {std::uint32_t(n)};
    } else {
        std::uint64_t sum = 0;
        for (std::size_t i = 0; i < c.counts.size(); ++i) {
            if (c.counts[i] < need)
                checks.fail(ptr + "/counts/" + std::to_string(i), need_text(c.counts[i]));
            out.first.push_back(std::uint32_t(sum));
            out.count.push_back(c.counts[i]);
            sum += c.counts[i];
        }
        if (sum != n)
            checks.fail(ptr + "/counts", "the strands' control points add up to " +
                                             std::to_string(sum) + " but \"points\" holds " +
                                             std::to_string(n));
    }
    if (!c.root_uvs.empty()) {
        if (c.root_uvs.size() != 2 * out.count.size())
            checks.fail(ptr + "/root_uvs", "expected one (u, v) pair per strand (" +
                                               std::to_string(2 * out.count.size()) +
                                               " numbers), got " +
                                               std::to_string(c.root_uvs.size()));
        for (std::size_t i = 0; i < c.root_uvs.size(); ++i)
            if (!std::isfinite(c.root_uvs[i]))
                checks.fail(ptr + "/root_uvs/" + std::to_string(i), "must be a finite number");
    }
    if (!c.strand_random.empty()) {
        if (c.strand_random.size() != out.count.size())
            checks.fail(ptr + "/strand_random", "expected one number per strand (" +
                                                    std::to_string(out.count.size()) + "), got " +
                                                    std::to_string(c.strand_random.size()));
        for (std::size_t i = 0; i < c.strand_random.size(); ++i)
            if (!(c.strand_random[i] >= 0.f && c.strand_random[i] <= 1.f))
                checks.fail(ptr + "/strand_random/" + std::to_string(i), "must be in [0, 1]");
    }
    return out;
}

// Segments of a strand of `count` control points.
std::uint32_t segments_of(const BasisInfo& basis, std::uint32_t count) {
    return count - (basis.min_points - 1);
}

void build(ShapeBuild& b) {
    const ShapeDesc& s = b.shape;
    if (b.emissive)
        b.fail(b.ptr + "/emission", "curves cannot emit (light sampling has no curve emitters)");
    const Strands st = check_strands(s, b.ptr, b);
    const CurveData& c = s.curves;
    std::uint64_t total = 0;
    for (std::uint32_t k : st.count) total += segments_of(*st.basis, k);
    // Segments count against the scene's primitive limit as triangles do.
    b.reserve_triangles(total, b.ptr + "/points");

    CurveGeom g;
    g.shape = b.index;
    g.basis = st.basis->basis;
    g.flat = st.flat;
    // A radius is a length: under a transform that scales unevenly it becomes the cube root of
    // the volume scale (as Cycles' hair takes it; the tube stays round).
    const glm::dmat3 lin(b.xf);
    const double det = std::fabs(glm::determinant(lin));
    const double rscale = std::cbrt(det);
    const double l0 = glm::length(lin[0]), l1 = glm::length(lin[1]), l2 = glm::length(lin[2]);
    const double lmax = std::max({l0, l1, l2}), lmin = std::min({l0, l1, l2});
    if (lmax > lmin * (1.0 + 1e-6) || std::fabs(glm::dot(lin[0], lin[1])) > 1e-6 * l0 * l1 ||
        std::fabs(glm::dot(lin[0], lin[2])) > 1e-6 * l0 * l2 ||
        std::fabs(glm::dot(lin[1], lin[2])) > 1e-6 * l1 * l2)
        b.warn(b.place() +
               ": curves under a transform that scales unevenly or shears keep a round cross "
               "section (radius times the cube root of the volume scale)");
    const std::size_t n = c.num_points();
    g.vertices.resize(n);
    Bounds3 world, object;
    double max_coord = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        const glm::dvec3 po(c.points[3 * i], c.points[3 * i + 1], c.points[3 * i + 2]);
        const double r = c.radius.size() == 1 ? c.radius[0] : c.radius[i];
        const glm::dvec3 pw = glm::dvec3(b.xf * glm::dvec4(po, 1.0));
        const float rw = float(r * rscale);
        if (!(rw > 0.f) || !std::isfinite(rw))
            b.fail(b.ptr + "/radius", "the transformed radius is not a positive float");
        g.vertices[i] = glm::vec4(Vec3(pw), rw);
        object.lo = glm::min(object.lo, Vec3(po - r));
        object.hi = glm::max(object.hi, Vec3(po + r));
        world.lo = glm::min(world.lo, Vec3(pw) - rw);
        world.hi = glm::max(world.hi, Vec3(pw) + rw);
        max_coord = std::max(max_coord, largest_magnitude(pw) + double(rw));
    }
    // Deformation motion: every step 3n finite numbers (checked with motion blur on or off);
    // with `deform` the steps' points through xf, each with its point's still radius.
    const std::string mp = b.ptr + "/motion_positions";
    for (std::size_t k = 0; k < s.motion_positions.size(); ++k) {
        const std::vector<float>& in = s.motion_positions[k];
        const std::string sp = mp + "/" + std::to_string(k);
        if (in.size() != 3 * n)
            b.fail(sp, "expected " + std::to_string(3 * n) +
                           " numbers (3 per control point: the curves have " + std::to_string(n) +
                           " points), got " + std::to_string(in.size()));
        for (std::size_t i = 0; i < in.size(); ++i)
            if (!std::isfinite(in[i]))
                b.fail(sp + "/" + std::to_string(i), "must be a finite number");
        if (!b.deform) continue;
        std::vector<glm::vec4> step(n);
        for (std::size_t i = 0; i < n; ++i) {
            const glm::dvec3 po(in[3 * i], in[3 * i + 1], in[3 * i + 2]);
            const glm::dvec3 pw = glm::dvec3(b.xf * glm::dvec4(po, 1.0));
            const float rw = g.vertices[i].w;
            const double r = c.radius.size() == 1 ? c.radius[0] : c.radius[i];
            step[i] = glm::vec4(Vec3(pw), rw);
            object.lo = glm::min(object.lo, Vec3(po - r));
            object.hi = glm::max(object.hi, Vec3(po + r));
            world.lo = glm::min(world.lo, Vec3(pw) - rw);
            world.hi = glm::max(world.hi, Vec3(pw) + rw);
            max_coord = std::max(max_coord, largest_magnitude(pw) + double(rw));
        }
        g.step_vertices.push_back(std::move(step));
    }
    g.max_coord = float(max_coord);
    const std::size_t strands = st.count.size();
    g.segments.reserve(total);
    g.segment_strand.reserve(total);
    g.strand_first.reserve(strands + 1);
    for (std::size_t k = 0; k < strands; ++k) {
        g.strand_first.push_back(std::uint32_t(g.segments.size()));
        const std::uint32_t ns = segments_of(*st.basis, st.count[k]);
        for (std::uint32_t j = 0; j < ns; ++j) {
            g.segments.push_back(st.first[k] + j);
            g.segment_strand.push_back(std::uint32_t(k));
            if (g.flat) {
                float r = 0.f;
                for (unsigned q = 0; q < st.basis->min_points; ++q)
                    r = std::max(r, g.vertices[st.first[k] + j + q].w);
                g.segment_radius.push_back(r);
            }
        }
    }
    g.strand_first.push_back(std::uint32_t(g.segments.size()));
    if (!c.root_uvs.empty()) {
        g.root_uvs.resize(strands);
        for (std::size_t k = 0; k < strands; ++k)
            g.root_uvs[k] = Vec2(c.root_uvs[2 * k], c.root_uvs[2 * k + 1]);
    }
    g.strand_random = c.strand_random;  // (empty: add_curves hashes the indices when needed)
    b.add_curves(std::move(g), world, object);
}

// A cubic strand's end (the first segment's start, or the last segment's end) and the clipping
// plane there: Embree's cubic tubes end with the sweep's circle at the end parameter (open, no
// cap), while POV-Ray's sphere_sweep closes each end with the end sphere. The circle lies in the
// plane normal to the axis tangent c' through c - r r' c' / |c'|^2 (the envelope's
// characteristic circle), which clips the sphere off. `end`: the last segment's u = 1 (else
// the first's u = 0). Returns the SDL plane that removes what lies beyond the end, or "".
std::string pov_end_plane(const BasisInfo& basis, const CurveData& c, std::size_t first, bool end) {
    glm::dvec3 p[4];
    double r[4];
    for (std::size_t q = 0; q < 4; ++q) {
        const std::size_t i = first + q;
        p[q] = glm::dvec3(c.points[3 * i], c.points[3 * i + 1], c.points[3 * i + 2]);
        r[q] = c.radius.size() == 1 ? c.radius[0] : c.radius[i];
    }
    glm::dvec3 at, d;
    double ra, dr;
    if (basis.basis == CurveGeom::Basis::BSpline) {
        const std::size_t a =
            end ? 1 : 0;  // c = (p_a + 4 p_a+1 + p_a+2) / 6, c' = (p_a+2 - p_a) / 2
        at = (p[a] + 4.0 * p[a + 1] + p[a + 2]) / 6.0;
        ra = (r[a] + 4.0 * r[a + 1] + r[a + 2]) / 6.0;
        d = 0.5 * (p[a + 2] - p[a]);
        dr = 0.5 * (r[a + 2] - r[a]);
    } else {  // Catmull-Rom: c = p_a+1, c' = (p_a+2 - p_a) / 2
        const std::size_t a = end ? 1 : 0;
        at = p[a + 1];
        ra = r[a + 1];
        d = 0.5 * (p[a + 2] - p[a]);
        dr = 0.5 * (r[a + 2] - r[a]);
    }
    const double len2 = glm::dot(d, d);
    if (!(len2 > 0.0)) return "";
    const glm::dvec3 n = d / std::sqrt(len2);
    const double offset = glm::dot(n, at - ra * dr / len2 * d);
    // plane { n, o } is the half-space dot(n, x) < o: the root keeps dot(n, x) >= o, the tip
    // dot(n, x) <= o.
    return end ? " plane { " + pov_vec(-n) + ", " + pov_num(-offset) + " }"
               : " plane { " + pov_vec(n) + ", " + pov_num(offset) + " }";
}

// Each strand as a POV-Ray sphere_sweep of the same spline (its radius interpolated by the same
// basis, as Embree's), a cubic one with its end spheres clipped off (pov_end_plane), in one
// union carrying the shape's texture and transform. Checked against Facet by povray-facet
// (tests/povray/curves_hair.json, crosscheck.py).
void pov(PovShapeOut& o) {
    const ShapeDesc& s = o.shape;
    struct Checks final : BuildChecks {
        const PovShapeOut& out;
        explicit Checks(const PovShapeOut& o) : out(o) {}
        [[noreturn]] void fail(const std::string& p, const std::string& m) const override {
            out.fail(p, m);
            __builtin_unreachable();
        }
    } checks(o);
    const Strands st = check_strands(s, o.pointer, checks);
    if (st.flat)
        o.fail(o.pointer + "/profile",
               "flat curves (ribbons facing each ray) have no POV-Ray equivalent: only round "
               "curves are exported (as sphere_sweep)");
    if (o.emits) o.fail(o.pointer + "/emission", "curves cannot emit");
    if (o.reads_uv) o.fail_uv("POV-Ray's sphere_sweep has no UV coordinates");
    const CurveData& c = s.curves;
    // (One strand is its sphere_sweep alone: POV-Ray warns of a union of one object.)
    const bool one = st.count.size() == 1;
    std::string head = one ? "" : "union {\n";
    for (std::size_t k = 0; k < st.count.size(); ++k) {
        const bool cubic = st.basis->basis != CurveGeom::Basis::Linear;
        head += std::string(one ? "" : "  ") + (cubic ? "difference { " : "") + "sphere_sweep { " +
                std::string(st.basis->pov) + " " + std::to_string(st.count[k]);
        for (std::uint32_t j = 0; j < st.count[k]; ++j) {
            const std::size_t i = st.first[k] + j;
            const glm::dvec3 p(c.points[3 * i], c.points[3 * i + 1], c.points[3 * i + 2]);
            head += ", " + pov_vec(p) + ", " +
                    pov_num(c.radius.size() == 1 ? c.radius[0] : c.radius[i]);
        }
        head += " }";
        if (cubic)
            head += pov_end_plane(*st.basis, c, st.first[k], false) +
                    pov_end_plane(*st.basis, c, st.first[k] + st.count[k] - 4, true) + " }";
        head += one ? "" : "\n";
    }
    if (one) head.erase(head.size() - 2);  // the object's own closing brace is object()'s
    o.object(head, false);
}

}  // namespace

float curve_random(std::uint32_t i) {
    return cycles::to_unit(cycles::hash_uint2(i, 0u));
}

extern const ShapeKindDef kCurvesKind{
    ShapeKind::Curves,
    "curves",
    "strands (hair, fur, grass) along curves with a radius per control point: round tubes or "
    "flat ribbons facing each ray (scenes/FORMAT.md, \"Curves\"); a hit's normal is the "
    "tube's, its tangent (`dpdu`) the strand's direction, its uv the strand's root UV and "
    "its random value (a `hair_info` texture's `random`) `strand_random`'s or Cycles' hash of "
    "the strand's index",
    {{"basis", FieldType::Text, true, &ShapeDesc::basis, "-",
      "`linear` (straight segments through the points, >= 2 per strand), `bspline` (uniform "
      "cubic B-spline, >= 4: it approximates the points) or `catmull_rom` (>= 4: it passes "
      "through every point but the first and last of each strand, which set the end tangents)"},
     {"profile", FieldType::Text, false, &ShapeDesc::profile, "round",
      "`round` (tubes: a swept sphere) or `flat` (ribbons of the same width facing each ray, "
      "shaded with the normal of the tube they stand for)"},
     {"points", FieldType::CurveArrays, true, &ShapeDesc::curves, "-",
      "flat arrays: `points` [x0, y0, z0, x1, ...] (the control points, strand after strand), "
      "`radius` (a number for every point, or an array of one per point; each > 0), optional "
      "`counts` (the number of control points of each strand, in order; absent: one strand), "
      "optional `root_uvs` [u0, v0, u1, ...] (one pair per strand: the texture coordinates of "
      "every hit on it; needed when the material is textured), optional `strand_random` (one "
      "number in [0, 1] per strand: its random value, which a `hair_info` texture reads; "
      "absent: Cycles' hash of the strand's index)"}},
    build,
    nullptr,
    pov};

}  // namespace facet::render
