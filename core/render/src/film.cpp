// Film resolve and merge, render part files (facet/render/film.h).
#include "facet/render/film.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <bit>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace facet::render {

double from_fixed(FixedSum s) {
    // int128 -> double rounds to nearest (libgcc); the power-of-two scale is exact.
    return double(s) * 0x1p-60;
}
static_assert(kFixedFracBits == 60, "from_fixed's scale");

Image Film::resolve(bool shadow_catcher_pass) const {
    Image img(width(), height());
    if (has_alpha()) {
        img.add_alpha(0.f);
        for (std::size_t i = 0; i < m_alpha.size(); ++i) {
            const std::uint32_t n = m_counts[i];
            if (n == 0) continue;
            const double a = from_fixed(m_alpha[i]) / double(n);
            img.alpha()[i] = float(std::clamp(a, 0.0, 1.0));
        }
    }
    for (std::size_t i = 0; i < m_sums.size(); ++i) {
        const std::uint32_t n = m_counts[i];
        if (n == 0) continue;  // black
        const double inv = 1.0 / double(n);
        const FixedRgb& s = m_sums[i];
        img.pixels()[i] = Rgb(float(from_fixed(s.c[0]) * inv), float(from_fixed(s.c[1]) * inv),
                              float(from_fixed(s.c[2]) * inv));
    }
    if (has_catcher()) resolve_catcher(img, shadow_catcher_pass);
    return img;
}

void Film::catcher_ratio(std::size_t i, double r[3], double& coverage) const {
    using C = CatcherSums;
    const double inv = 1.0 / double(m_counts[i]);
    const FixedSum* c = &m_catcher[i * kCatcherSums];
    // The combined pass's coverage (1 without alpha: an opaque film).
    coverage = has_alpha() ? from_fixed(m_alpha[i]) * inv : 1.0;
    const double a_c = std::clamp(coverage, 0.0, 1.0);
    // The light the catcher kept, per channel, then over white by the combined coverage.
    for (int k = 0; k < 3; ++k) {
        const FixedSum caught = c[C::kCatcher + std::size_t(k)];
        const double ratio =
            c[C::kCount] != 0 && caught != 0
                ? from_fixed(m_sums[i].c[k] - c[C::kMatte + std::size_t(k)]) / from_fixed(caught)
                : 1.0;
        r[k] = 1.0 - a_c + a_c * ratio;
    }
}

void Film::resolve_catcher(Image& img, bool shadow_catcher_pass) const {
    using C = CatcherSums;
    if (shadow_catcher_pass && !img.has_alpha()) img.add_alpha(0.f);
    for (std::size_t i = 0; i < m_sums.size(); ++i) {
        const std::uint32_t n = m_counts[i];
        if (n == 0) continue;
        const double inv = 1.0 / double(n);
        const FixedSum* c = &m_catcher[i * kCatcherSums];
        double r[3], coverage;
        catcher_ratio(i, r, coverage);
        double matte[3];
        for (int k = 0; k < 3; ++k) matte[k] = from_fixed(c[C::kMatte + std::size_t(k)]) * inv;
        const double a_m =
            std::clamp(1.0 - from_fixed(c[C::kSplitT]) * inv - (1.0 - coverage), 0.0, 1.0);
        Rgb& px = img.pixels()[i];
        if (shadow_catcher_pass) {  // Cycles' Combined with the pass: the matte alone
            px = Rgb(float(matte[0]), float(matte[1]), float(matte[2]));
            img.alpha()[i] = float(a_m);
            continue;
        }
        const double shadow = 1.0 - std::clamp((r[0] + r[1] + r[2]) / 3.0, 0.0, 1.0);
        const double alpha = (1.0 - a_m) * shadow + a_m;
        if (has_alpha()) {
            px = Rgb(float(matte[0]), float(matte[1]), float(matte[2]));
            img.alpha()[i] = float(alpha);
        } else {
            for (int k = 0; k < 3; ++k)
                px[k] = float(matte[k] +
                              from_fixed(c[C::kBackground + std::size_t(k)]) * inv * (1.0 - alpha));
        }
    }
}

Image Film::resolve_shadow_catcher_pass() const {
    Image img(width(), height());
    std::fill(img.pixels().begin(), img.pixels().end(), Rgb(1.f));
    if (!has_catcher()) return img;
    for (std::size_t i = 0; i < m_sums.size(); ++i) {
        if (m_counts[i] == 0) continue;
        double r[3], coverage;
        catcher_ratio(i, r, coverage);
        img.pixels()[i] = Rgb(float(r[0]), float(r[1]), float(r[2]));
    }
    return img;
}

void Film::add(const Film& o) {
    const Region& r = o.m_region;
    if (r.x0 < m_region.x0 || r.y0 < m_region.y0 || r.x1 > m_region.x1 || r.y1 > m_region.y1)
        throw std::logic_error("Film::add: region outside the film");
    if (has_alpha() != o.has_alpha())
        throw std::logic_error("Film::add: one film has alpha and the other not");
    if (has_catcher() != o.has_catcher())
        throw std::logic_error("Film::add: one film has shadow-catcher sums and the other not");
    for (int y = r.y0; y < r.y1; ++y) {
        for (int x = r.x0; x < r.x1; ++x) {
            const std::size_t src =
                std::size_t(y - r.y0) * std::size_t(r.width()) + std::size_t(x - r.x0);
            const std::size_t dst =
                std::size_t(y - m_region.y0) * std::size_t(width()) + std::size_t(x - m_region.x0);
            m_sums[dst] += o.m_sums[src];
            m_counts[dst] += o.m_counts[src];
            if (!m_alpha.empty()) m_alpha[dst] += o.m_alpha[src];
            if (!m_catcher.empty())
                for (std::size_t k = 0; k < kCatcherSums; ++k)
                    m_catcher[dst * kCatcherSums + k] += o.m_catcher[src * kCatcherSums + k];
        }
    }
}

namespace {

// The first line of a part file of version 1, 2 and 3 (film.h).
constexpr const char* kPartMagics[] = {"FACETPART 1", "FACETPART 2", "FACETPART 3"};

std::string region_text(const Region& r) {
    return "[" + std::to_string(r.x0) + ", " + std::to_string(r.y0) + ", " + std::to_string(r.x1) +
           ", " + std::to_string(r.y1) + ")";
}

}  // namespace

void write_part(const RenderPart& part, const std::string& path) {
    const PartInfo& p = part.info;
    const bool alpha = part.film.has_alpha();
    const bool catcher = part.film.has_catcher();
    const int version = catcher ? 3 : alpha ? 2 : 1;
    nlohmann::json h{{"format", "facet-part"},
                     {"version", version},
                     {"scene", p.scene},
                     {"fingerprint", p.fingerprint},
                     {"width", p.width},
                     {"height", p.height},
                     {"region", {p.region.x0, p.region.y0, p.region.x1, p.region.y1}},
                     {"samples", {p.sample_begin, p.sample_end}},
                     {"seed", p.seed},
                     {"fixed_point_fraction_bits", kFixedFracBits}};
    std::ofstream out(path, std::ios::binary);
    if (!out) throw std::runtime_error(path + ": cannot create the part file");
    if (alpha || catcher) h["alpha"] = alpha;
    if (catcher) h["shadow_catcher"] = true;
    out << kPartMagics[version - 1] << "\n" << h.dump() << "\n";
    // Little-endian: the host's order on every platform Facet builds for (x86-64, aarch64).
    static_assert(std::endian::native == std::endian::little);
    const std::vector<FixedRgb>& sums = part.film.sum_values();
    for (std::size_t i = 0; i < sums.size(); ++i) {
        out.write(reinterpret_cast<const char*>(sums[i].c), sizeof sums[i].c);
        if (alpha)
            out.write(reinterpret_cast<const char*>(&part.film.alpha_values()[i]),
                      sizeof(FixedSum));
        if (catcher)
            out.write(reinterpret_cast<const char*>(&part.film.catcher_values()[i * kCatcherSums]),
                      std::streamsize(kCatcherSums * sizeof(FixedSum)));
    }
    if (!out) throw std::runtime_error(path + ": cannot write the part file");
}

RenderPart read_part(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw std::runtime_error(path + ": cannot open the part file");
    auto bad = [&](const std::string& why) {
        return std::runtime_error(path + ": not a valid Facet part file: " + why);
    };
    std::string magic, header;
    int version = 0;
    if (std::getline(in, magic))
        for (int v = 1; v <= 3; ++v)
            if (magic == kPartMagics[v - 1]) version = v;
    if (version == 0) throw bad("missing 'FACETPART 1' (or 2, 3) line");
    if (!std::getline(in, header)) throw bad("missing header line");
    RenderPart part;
    PartInfo& p = part.info;
    bool alpha = version == 2;
    const bool catcher = version == 3;
    try {
        const nlohmann::json h = nlohmann::json::parse(header);
        if (catcher) alpha = h.at("alpha").get<bool>();
        if (h.at("format") != "facet-part" || h.at("version") != version ||
            h.value("alpha", false) != alpha || h.value("shadow_catcher", false) != catcher)
            throw bad("unsupported format or version");
        if (h.at("fixed_point_fraction_bits") != kFixedFracBits)
            throw bad("fixed-point format differs from this build's");
        p.scene = h.at("scene").get<std::string>();
        p.fingerprint = h.at("fingerprint").get<std::uint64_t>();
        p.width = h.at("width").get<int>();
        p.height = h.at("height").get<int>();
        const auto& r = h.at("region");
        const auto& s = h.at("samples");
        if (r.size() != 4 || s.size() != 2) throw bad("region needs 4 numbers, samples 2");
        p.region = {r[0].get<int>(), r[1].get<int>(), r[2].get<int>(), r[3].get<int>()};
        p.sample_begin = s[0].get<int>();
        p.sample_end = s[1].get<int>();
        p.seed = h.at("seed").get<std::uint64_t>();
    } catch (const nlohmann::json::exception& e) {
        throw bad(std::string("header: ") + e.what());
    }
    const Region& r = p.region;
    if (p.width < 1 || p.height < 1 || r.empty() || r.x0 < 0 || r.y0 < 0 || r.x1 > p.width ||
        r.y1 > p.height)
        throw bad("region " + region_text(r) + " is empty or outside the " +
                  std::to_string(p.width) + "x" + std::to_string(p.height) + " image");
    if (p.sample_begin < 0 || p.sample_end <= p.sample_begin)
        throw bad("empty or negative sample range");
    part.film = Film(r, alpha, catcher);
    const std::size_t n = std::size_t(r.width()) * std::size_t(r.height());
    FixedRgb* sums = part.film.sums();
    FixedSum* alpha_sums = part.film.alpha_sums();
    FixedSum* catcher_sums = part.film.catcher_sums();
    for (std::size_t i = 0; i < n; ++i) {
        if (!in.read(reinterpret_cast<char*>(sums[i].c), sizeof sums[i].c) ||
            (alpha && !in.read(reinterpret_cast<char*>(&alpha_sums[i]), sizeof(FixedSum))) ||
            (catcher && !in.read(reinterpret_cast<char*>(&catcher_sums[i * kCatcherSums]),
                                 std::streamsize(kCatcherSums * sizeof(FixedSum)))))
            throw bad("truncated: expected " + std::to_string(n) + " pixels");
    }
    if (in.peek() != std::char_traits<char>::eof()) throw bad("trailing data after the pixels");
    std::uint32_t* counts = part.film.counts();
    for (std::size_t i = 0; i < n; ++i) counts[i] = std::uint32_t(p.sample_end - p.sample_begin);
    return part;
}

Film merge_parts(const std::vector<RenderPart>& parts, const std::vector<std::string>& names) {
    if (parts.empty()) throw std::runtime_error("merge: no parts given");
    auto name = [&](std::size_t i) {
        return i < names.size() ? names[i] : "part " + std::to_string(i);
    };
    const PartInfo& first = parts[0].info;
    int end = 0;
    for (std::size_t i = 0; i < parts.size(); ++i) {
        const PartInfo& p = parts[i].info;
        if (p.width != first.width || p.height != first.height)
            throw std::runtime_error(name(i) + ": image size " + std::to_string(p.width) + "x" +
                                     std::to_string(p.height) + " differs from " + name(0) + "'s " +
                                     std::to_string(first.width) + "x" +
                                     std::to_string(first.height));
        if (p.seed != first.seed)
            throw std::runtime_error(name(i) + ": rendered with seed " + std::to_string(p.seed) +
                                     ", " + name(0) + " with seed " + std::to_string(first.seed));
        if (p.fingerprint != first.fingerprint)
            throw std::runtime_error(name(i) + ": from a different scene or render settings than " +
                                     name(0) + " (scene '" + p.scene + "' vs '" + first.scene +
                                     "')");
        const Film& f = parts[i].film;
        if (f.has_alpha() != parts[0].film.has_alpha())
            throw std::runtime_error(name(i) + (f.has_alpha() ? " has" : " has no") +
                                     " alpha channel, " + name(0) +
                                     (f.has_alpha() ? " has none" : " has one"));
        if (f.has_catcher() != parts[0].film.has_catcher())
            throw std::runtime_error(name(i) + (f.has_catcher() ? " has" : " has no") +
                                     " shadow-catcher sums, " + name(0) +
                                     (f.has_catcher() ? " has none" : " has them"));
        if (!(f.region() == p.region))
            throw std::runtime_error(name(i) + ": film does not match its region");
        for (std::uint32_t c : f.count_values()) {
            if (c != std::uint32_t(p.sample_end - p.sample_begin))
                throw std::runtime_error(name(i) + ": incomplete part (a cancelled render)");
        }
        end = std::max(end, p.sample_end);
        for (std::size_t j = 0; j < i; ++j) {
            const PartInfo& q = parts[j].info;
            if (p.region.intersects(q.region) && p.sample_begin < q.sample_end &&
                q.sample_begin < p.sample_end) {
                const Region ov{
                    std::max(p.region.x0, q.region.x0), std::max(p.region.y0, q.region.y0),
                    std::min(p.region.x1, q.region.x1), std::min(p.region.y1, q.region.y1)};
                throw std::runtime_error(
                    name(i) + " and " + name(j) + " overlap: both cover samples [" +
                    std::to_string(std::max(p.sample_begin, q.sample_begin)) + ", " +
                    std::to_string(std::min(p.sample_end, q.sample_end)) + ") of pixels " +
                    region_text(ov));
            }
        }
    }
    Film out(Region{0, 0, first.width, first.height}, parts[0].film.has_alpha(),
             parts[0].film.has_catcher());
    for (const RenderPart& p : parts) out.add(p.film);
    const std::vector<std::uint32_t>& counts = out.count_values();
    for (std::size_t i = 0; i < counts.size(); ++i) {
        if (counts[i] != std::uint32_t(end)) {
            const int x = int(i % std::size_t(first.width)), y = int(i / std::size_t(first.width));
            throw std::runtime_error("merge: pixel (" + std::to_string(x) + ", " +
                                     std::to_string(y) + ") has " + std::to_string(counts[i]) +
                                     " of samples [0, " + std::to_string(end) +
                                     "): no part covers the rest");
        }
    }
    return out;
}

}  // namespace facet::render
