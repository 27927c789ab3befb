// `facet brdf eval | sample | plot | models`: look at a reflection model from the shell.
#include <fmt/format.h>
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <pcg_random.hpp>

#include <cstdio>
#include <memory>

#include "commands.h"
#include "facet/reflectance.h"
#include "model_args.h"
#include "plot.h"

namespace facet::cli {

namespace {

struct BrdfOptions {
    std::string model;
    std::string wi = "45,0", wo = "45,180";
    bool json = false;
    int count = 8;
    std::uint64_t seed = 1;
    std::string output = "lobe.png";
    float theta_plot = 45.f;
    bool log_scale = false;
};

nlohmann::json rgb_json(const Rgb& c) {
    return {c.r, c.g, c.b};
}

std::string flags_name(BxDFFlags f) {
    std::string s;
    if (any(f & BxDFFlags::Diffuse)) s += "diffuse";
    if (any(f & BxDFFlags::Glossy)) s += s.empty() ? "glossy" : "|glossy";
    if (any(f & BxDFFlags::Specular)) s += s.empty() ? "specular" : "|specular";
    if (any(f & BxDFFlags::Transmission)) s += s.empty() ? "transmission" : "|transmission";
    return s.empty() ? "none" : s;
}

void run_eval(const BrdfOptions& o, const std::vector<std::string>& extras) {
    Material m = material_from_args(o.model, extras);
    Vec3 wi = direction_from_degrees(o.wi, "--wi"), wo = direction_from_degrees(o.wo, "--wo");
    Rgb f = m.f(wo, wi);
    float pdf = m.pdf(wo, wi);
    if (o.json) {
        nlohmann::json j{
            {"model", o.model}, {"f", rgb_json(f)}, {"pdf", pdf}, {"flags", flags_name(m.flags())}};
        std::puts(j.dump(2).c_str());
        return;
    }
    fmt::print("model {}  lobes {}\n", o.model, flags_name(m.flags()));
    fmt::print("f   = {:.6g} {:.6g} {:.6g}  [1/sr, no cosine]\n", f.r, f.g, f.b);
    fmt::print("pdf = {:.6g}  [1/sr, of sample_f]\n", pdf);
}

void run_sample(const BrdfOptions& o, const std::vector<std::string>& extras) {
    if (o.count < 1 || o.count > 10000000) throw std::runtime_error("--count: must be in [1, 1e7]");
    Material m = material_from_args(o.model, extras);
    Vec3 wo = direction_from_degrees(o.wo, "--wo");
    pcg32 rng(o.seed);
    auto uniform = [&] { return std::min(float(rng() >> 8) * 0x1p-24f, kOneMinusEpsilon); };
    nlohmann::json all = nlohmann::json::array();
    if (!o.json)
        fmt::print("{:>10} {:>10} {:>12} {:>12} {:>12} {:>12} {}\n", "theta_i", "phi_i", "f.r",
                   "f.g", "f.b", "pdf", "lobe");
    for (int i = 0; i < o.count; ++i) {
        float uc = uniform();
        Vec2 u(uniform(), uniform());
        auto s = m.sample_f(wo, uc, u);
        if (!s) {
            if (o.json)
                all.push_back(nullptr);
            else
                fmt::print("{:>10}\n", "none");
            continue;
        }
        Vec2 d = degrees_of(s->wi);
        if (o.json) {
            all.push_back({{"wi", {s->wi.x, s->wi.y, s->wi.z}},
                           {"theta", d.x},
                           {"phi", d.y},
                           {"f", rgb_json(s->f)},
                           {"pdf", s->pdf},
                           {"flags", flags_name(s->flags)}});
        } else {
            fmt::print("{:10.4f} {:10.4f} {:12.6g} {:12.6g} {:12.6g} {:12.6g} {}\n", d.x, d.y,
                       s->f.r, s->f.g, s->f.b, s->pdf, flags_name(s->flags));
        }
    }
    if (o.json) std::puts(all.dump(2).c_str());
}

// Two panels: left, the lobe f(wo, wi) cos(theta_o) in the plane of incidence as a polar curve
// (per channel, normalised to its maximum; delta lobes as arrows of length = reflectance);
// right, rho(wi -> 2pi) against theta_i per channel.
void run_plot(const BrdfOptions& o, const std::vector<std::string>& extras) {
    Material m = material_from_args(o.model, extras);
    if (!(o.theta_plot >= 0.f && o.theta_plot < 90.f))
        throw std::runtime_error("--theta: must be in [0, 90) degrees");
    const int W = 1200, H = 560;
    Canvas c(W, H, {255, 255, 255});
    const Color8 black{0, 0, 0}, grey{170, 170, 170};
    Color8 channel[3] = {{210, 40, 40}, {40, 160, 60}, {40, 80, 220}};
    const float deg = kPi / 180.f;

    // Left panel: polar lobe.
    float cx = 300.f, cy = 470.f, R = 260.f;
    Vec3 wi = spherical_direction(o.theta_plot * deg, 0.f);  // light from +x side
    const int n = 721;
    std::vector<Rgb> lobe(n);
    Rgb peak(0.f);
    for (int k = 0; k < n; ++k) {
        float t = (-90.f + 180.f * k / (n - 1)) * deg;
        Vec3 wo(std::sin(t), 0.f, std::cos(t));
        lobe[k] = m.f(wo, wi) * std::fmax(wo.z, 0.f);
        peak = glm::max(peak, lobe[k]);
    }
    // A grey material draws one black curve rather than three on top of each other.
    if (peak.r == peak.g && peak.g == peak.b) channel[0] = channel[1] = channel[2] = black;
    for (int a = 0; a <= 180; a += 30) {  // angle grid
        float t = (a - 90.f) * deg;
        c.dashed_line(cx, cy, cx + R * std::sin(t), cy - R * std::cos(t), grey);
    }
    for (int k = 1; k < 90; ++k)
        c.line(cx + R * std::sin((k - 1 - 45) * 2 * deg), cy - R * std::cos((k - 1 - 45) * 2 * deg),
               cx + R * std::sin((k - 45) * 2 * deg), cy - R * std::cos((k - 45) * 2 * deg), grey,
               1.f);
    c.line(cx - R, cy, cx + R, cy, black, 1.5f);
    // Incident direction (toward the light, +x side) and the mirror direction.
    c.line(cx, cy, cx + R * wi.x, cy - R * wi.z, {230, 150, 0}, 2.5f);
    c.dashed_line(cx, cy, cx - R * wi.x, cy - R * wi.z, {230, 150, 0});
    auto scale = [&](float v, float pk) {
        if (!(pk > 0.f)) return 0.f;
        if (!o.log_scale) return v / pk;
        // Log scale over 4 decades below the peak.
        return v > pk * 1e-4f ? 1.f + std::log10(v / pk) / 4.f : 0.f;
    };
    for (int ch = 0; ch < 3; ++ch)
        for (int k = 1; k < n; ++k) {
            float t0 = (-90.f + 180.f * (k - 1) / (n - 1)) * deg,
                  t1 = (-90.f + 180.f * k / (n - 1)) * deg;
            float r0 = R * scale(lobe[k - 1][ch], peak[ch]), r1 = R * scale(lobe[k][ch], peak[ch]);
            c.line(cx + r0 * std::sin(t0), cy - r0 * std::cos(t0), cx + r1 * std::sin(t1),
                   cy - r1 * std::cos(t1), channel[ch], 2.f);
        }
    if (is_specular(m.flags())) {
        if (m.mirror()) {
            Rgb r = m.mirror()->reflectance(wi.z);
            for (int ch = 0; ch < 3; ++ch)
                c.line(cx, cy, cx - R * r[ch] * wi.x, cy - R * r[ch] * wi.z, channel[ch], 3.f);
        }
    }
    c.text(20, 14, fmt::format("facet brdf plot: {}", o.model), black, 2.5f);
    c.text(20, 44,
           fmt::format("lobe f cos(theta_o) in the plane of incidence, theta_i = {:.1f} deg",
                       o.theta_plot),
           black, 1.6f);
    c.text(20, 88,
           o.log_scale ? "radius: log scale, 4 decades below the peak" : "radius: linear, peak = 1",
           black, 1.6f);
    c.text(20, 66, fmt::format("peak f cos = {:.4g} {:.4g} {:.4g} (r g b)", peak.r, peak.g, peak.b),
           black, 1.6f);
    c.text(cx + R * wi.x + 6, cy - R * wi.z - 14, "light", {230, 150, 0}, 1.6f);

    // Right panel: rho(wi -> 2pi) vs theta_i.
    float x0 = 680.f, y0 = 480.f, pw = 480.f, ph = 380.f;
    c.line(x0, y0, x0 + pw, y0, black, 1.5f);
    c.line(x0, y0, x0, y0 - ph, black, 1.5f);
    for (int k = 0; k <= 10; ++k) {
        float y = y0 - ph * k / 10.f;
        c.line(x0 + 1, y, x0 + pw, y, {225, 225, 225}, 1.f);
        if (k % 2 == 0) c.text(x0 - 34, y - 6, fmt::format("{:.1f}", k / 10.f), black, 1.5f);
    }
    for (int a = 0; a <= 90; a += 15) {
        float x = x0 + pw * a / 90.f;
        c.line(x, y0 + 1, x, y0 - ph, {225, 225, 225}, 1.f);
        c.text(x - 8, y0 + 8, fmt::format("{}", a), black, 1.5f);
    }
    const int m_pts = 46;
    std::vector<Rgb> rho(m_pts);
    for (int k = 0; k < m_pts; ++k) {
        float t = 89.f * k / (m_pts - 1);
        rho[k] = Rgb(directional_hemispherical(m, spherical_direction(t * deg, 0.f), 16).value);
    }
    for (int ch = 0; ch < 3; ++ch)
        for (int k = 1; k < m_pts; ++k)
            c.line(x0 + pw * (89.f * (k - 1) / (m_pts - 1)) / 90.f,
                   y0 - ph * std::clamp(rho[k - 1][ch], 0.f, 1.05f),
                   x0 + pw * (89.f * k / (m_pts - 1)) / 90.f,
                   y0 - ph * std::clamp(rho[k][ch], 0.f, 1.05f), channel[ch], 2.f);
    c.text(x0, 88, "directional-hemispherical reflectance rho(theta_i -> 2pi)", black, 1.6f);
    c.text(x0 + pw / 2 - 40, y0 + 30, "theta_i [deg]", black, 1.6f);
    c.write_png(o.output);
    fmt::print("wrote {}\n", o.output);
}

void print_models(bool markdown) {
    for (const auto& m : model_table()) {
        if (markdown) {
            fmt::print(
                "#### `{}`\n{}\n\n| parameter | type | default | meaning |\n|---|---|---|---|\n",
                m.name, m.summary);
            for (const auto& p : m.params) {
                const char* type = p.type == ParamType::Number      ? "number"
                                   : p.type == ParamType::Color     ? "colour"
                                   : p.type == ParamType::Bool      ? "bool"
                                   : p.type == ParamType::Materials ? "[material, material]"
                                                                    : "string";
                fmt::print("| `{}` | {} | {} | {} |\n", p.name, type, p.default_value, p.doc);
            }
            fmt::print("\n");
        } else {
            fmt::print("{}: {}\n", m.name, m.summary);
            for (const auto& p : m.params)
                fmt::print("    --{:<20} default {:<18} {}\n", p.name, p.default_value, p.doc);
        }
    }
}

}  // namespace

void add_brdf_commands(CLI::App& app) {
    auto opts = std::make_shared<BrdfOptions>();
    CLI::App* brdf = app.add_subcommand("brdf", "evaluate, sample and plot reflection models");
    brdf->require_subcommand(1);
    auto model_flags = [&](CLI::App* sub) {
        sub->add_option("--model", opts->model, "model name (see `facet brdf models`)")->required();
        sub->allow_extras();  // model parameters: --alpha 0.3 --fresnel conductor ...
        sub->footer("Model parameters are passed as --name value (see `facet brdf models`).");
    };

    CLI::App* eval = brdf->add_subcommand("eval", "print f(wo, wi) (RGB) and pdf(wo, wi)");
    model_flags(eval);
    eval->add_option("--wi", opts->wi, "light direction theta,phi in degrees")
        ->capture_default_str();
    eval->add_option("--wo", opts->wo, "view direction theta,phi in degrees")
        ->capture_default_str();
    eval->add_flag("--json", opts->json, "JSON output");
    eval->callback([opts, eval] { run_eval(*opts, eval->remaining()); });

    CLI::App* sample = brdf->add_subcommand("sample", "draw wi ~ sample_f(wo) and print them");
    model_flags(sample);
    sample->add_option("--wo", opts->wo, "view direction theta,phi in degrees")
        ->capture_default_str();
    sample->add_option("--count,-n", opts->count, "number of samples")->capture_default_str();
    sample->add_option("--seed", opts->seed, "PCG32 seed")->capture_default_str();
    sample->add_flag("--json", opts->json, "JSON output");
    sample->callback([opts, sample] { run_sample(*opts, sample->remaining()); });

    CLI::App* plot = brdf->add_subcommand("plot", "polar lobe plot and rho(theta_i) plot as PNG");
    model_flags(plot);
    plot->add_option("--theta", opts->theta_plot, "incidence angle of the lobe plot, degrees")
        ->capture_default_str();
    plot->add_flag("--log", opts->log_scale, "log radial scale (4 decades)");
    plot->add_option("-o,--output", opts->output, "PNG file")->capture_default_str();
    plot->callback([opts, plot] { run_plot(*opts, plot->remaining()); });

    CLI::App* models = brdf->add_subcommand("models", "list the models and their parameters");
    auto markdown = std::make_shared<bool>(false);
    models->add_flag("--markdown", *markdown, "print Markdown tables (docs/models.md)");
    models->callback([markdown] { print_models(*markdown); });
}

}  // namespace facet::cli
