// `facet render scene.json -o out.exr [-o out.png] [-o part.fpart] [--spp N] [--time S]
//  [--threads N] [--integrator direct|path] [--seed S] [--max-depth D] [--kernel auto|general]
//  [--light-selection auto|view|power|uniform|tree] [--region x0,y0,x1,y1] [--samples s0:s1]
//  [--shadow-catcher-pass FILE] [--explain]
//  [--quiet] [--stats-json FILE]`
// `facet merge part.fpart ... -o out.exr [-o out.png] [--shadow-catcher-pass FILE]`
//
// Errors (bad flags, a bad scene, an unwritable output) print "facet: <place>: <message>" and
// exit with a non-zero code: CLI11's codes for flag errors, 1 for everything else.
#include <fmt/format.h>
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <fstream>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "commands.h"
#include "facet/render/denoise.h"
#include "facet/render/gltf.h"
#include "facet/render/image.h"
#include "facet/render/render.h"
#include "facet/render/scene.h"

namespace facet::cli {

namespace {

struct RenderCmdOptions {
    std::string scene;
    std::vector<std::string> outputs;
    int spp = 0;
    double time_s = -1.0;
    int threads = 0;
    std::string integrator;
    std::int64_t seed = -1;
    int max_depth = -1;
    std::string kernel = "auto";
    std::string light_selection = "auto";
    std::string sampler = "sobol";
    bool explain = false;
    bool quiet = false;
    std::string stats_json;
    std::string region;   // "x0,y0,x1,y1"
    std::string samples;  // "s0:s1"
    double texture_memory_mib = double(render::kDefaultTextureMemory >> 20);
    bool denoise = false;
    std::string denoise_raw;           // the undenoised image
    std::string denoise_features;      // prefix of <prefix>.albedo.exr, .normal.exr, .depth.exr
    double adaptive_threshold = -1.0;  // < 0: the scene's
    int adaptive_min_samples = -1;
    std::string shadow_catcher_pass;  // the Shadow Catcher pass's image (.exr or .png)
};

// --shadow-catcher-pass FILE: an image file, or throws naming the command.
void check_pass_output(const std::string& path, const char* command);

// Parses "a<sep>b<sep>..." into exactly n non-negative integers, or throws naming the flag.
std::vector<int> parse_ints(const std::string& text, char sep, std::size_t n, const char* flag,
                            const char* form) {
    std::vector<int> v;
    std::size_t pos = 0;
    while (true) {
        std::size_t end = text.find(sep, pos);
        std::string item =
            text.substr(pos, end == std::string::npos ? std::string::npos : end - pos);
        std::size_t used = 0;
        int x = -1;
        try {
            x = std::stoi(item, &used);
        } catch (const std::exception&) {
            used = 0;
        }
        if (item.empty() || used != item.size() || x < 0)
            throw std::runtime_error(std::string("render: ") + flag + ": expected " + form +
                                     " (non-negative integers), got '" + text + "'");
        v.push_back(x);
        if (end == std::string::npos) break;
        pos = end + 1;
    }
    if (v.size() != n)
        throw std::runtime_error(std::string("render: ") + flag + ": expected " + form + ", got '" +
                                 text + "'");
    return v;
}

std::string extension_of(const std::string& path) {
    const auto dot = path.find_last_of('.');
    const auto slash = path.find_last_of('/');
    if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
    std::string e = path.substr(dot);
    std::transform(e.begin(), e.end(), e.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    return e;
}

void print_explain(const render::Scene& scene, const render::KernelChoice& k,
                   const render::ResolvedSettings& rs, render::LightSelection selection) {
    fmt::print("scene {}\n{}", scene.name(), scene.features().describe());
    fmt::print("integrator {}  spp {}  max_depth {}  seed {}  threads {}{}\n",
               render::integrator_name(rs.integrator), rs.spp, rs.max_depth, rs.seed, rs.threads,
               rs.time_budget_s > 0 ? fmt::format("  time budget {} s", rs.time_budget_s) : "");
    const render::LightSelection ls = render::resolve_light_selection(scene, selection);
    fmt::print(
        "light selection {}{}\n", render::light_selection_name(ls),
        selection == render::LightSelection::Auto
            ? fmt::format(" (auto: tree from {} local lights on)", render::kTreeMinLocalLights)
            : "");
    fmt::print("kernel {}\n", k.name);
    for (const auto& s : k.chosen) fmt::print("  chosen:  {}\n", s);
    for (const auto& s : k.skipped) fmt::print("  skipped: {}\n", s);
    std::fflush(stdout);
}

// A scene file, or a bare glTF file (.gltf, .glb) with its camera or one framing it and a
// constant environment (render::gltf_scene_description); the choices made go to stderr.
render::Scene load_scene_or_gltf(const std::string& path, const render::SceneLimits& limits) {
    const std::string e = extension_of(path);
    if (e != ".gltf" && e != ".glb") return render::load_scene(path, limits);
    // The image size of a bare glTF render; the file's camera aspect ratio sets the width.
    constexpr int kWidth = 640, kHeight = 480;
    std::vector<std::string> notes;
    const render::SceneDescription desc =
        render::gltf_scene_description(path, kWidth, kHeight, notes);
    for (const std::string& n : notes)
        std::fprintf(stderr, "facet: render: %s: %s\n", path.c_str(), n.c_str());
    return render::build_scene(desc, path, limits);
}

void report_render(const render::Scene& scene, const render::RenderStats& st,
                   const RenderCmdOptions& o);
void render_denoised(const render::Scene& scene, const render::RenderOptions& ro,
                     const render::ResolvedSettings& rs, const RenderCmdOptions& o);

void run_render(const RenderCmdOptions& o) {
    if (o.outputs.empty() && !o.explain)
        throw std::runtime_error("render: no output: give -o out.exr and/or -o out.png");
    for (const auto& out : o.outputs) {
        const std::string e = extension_of(out);
        if (e != ".exr" && e != ".png" && e != ".fpart")
            throw std::runtime_error("render: -o " + out +
                                     ": unknown output extension (use .exr, .png or .fpart)");
    }
    if (!o.shadow_catcher_pass.empty()) {
        check_pass_output(o.shadow_catcher_pass, "render");
        if (o.denoise)
            throw std::runtime_error(
                "render: --shadow-catcher-pass: not with --denoise (the pass is not denoised)");
    }
    if (o.kernel != "auto" && o.kernel != "general")
        throw std::runtime_error("render: --kernel: expected 'auto' or 'general', got '" +
                                 o.kernel + "'");

    // At least 1 MiB (render::kMinTextureMemory), at most 2^40 MiB; NaN fails both.
    if (!(o.texture_memory_mib >= 1.0 && o.texture_memory_mib <= 1099511627776.0))
        throw std::runtime_error(
            "render: --texture-memory: expected a size in MiB from 1 to "
            "2^40, got " +
            std::to_string(o.texture_memory_mib));
    render::SceneLimits limits;
    limits.texture_memory = std::uint64_t(o.texture_memory_mib * double(1 << 20));
    const render::Scene scene = load_scene_or_gltf(o.scene, limits);  // SceneError: file + path
    for (const std::string& w : scene.warnings())
        std::fprintf(stderr, "facet: render: warning: %s: %s\n", o.scene.c_str(), w.c_str());

    render::RenderOptions ro;
    ro.integrator = o.integrator;
    ro.spp = o.spp;
    if (o.time_s >= 0.0) ro.time_budget_s = o.time_s;
    ro.max_depth = o.max_depth;
    if (o.seed >= 0) ro.seed = std::uint64_t(o.seed);
    ro.threads = o.threads;
    ro.force_general_kernel = o.kernel == "general";
    ro.light_selection = o.light_selection == "uniform" ? render::LightSelection::Uniform
                         : o.light_selection == "power" ? render::LightSelection::Power
                         : o.light_selection == "tree"  ? render::LightSelection::Tree
                         : o.light_selection == "view"  ? render::LightSelection::View
                                                        : render::LightSelection::Auto;
    ro.independent_samples = o.sampler == "independent";
    if (o.adaptive_threshold >= 0.0) ro.adaptive_threshold = o.adaptive_threshold;
    ro.adaptive_min_samples = o.adaptive_min_samples;
    ro.shadow_catcher_pass = !o.shadow_catcher_pass.empty();
    ro.progress = o.quiet ? render::Progress::Mode::Silent : render::Progress::Mode::Auto;
    if (!o.region.empty()) {
        const std::vector<int> r = parse_ints(o.region, ',', 4, "--region", "x0,y0,x1,y1");
        ro.region = render::Region{r[0], r[1], r[2], r[3]};
    }
    if (!o.samples.empty()) {
        const std::vector<int> r = parse_ints(o.samples, ':', 2, "--samples", "s0:s1");
        ro.sample_begin = r[0];
        ro.sample_end = r[1];
        if (r[1] == 0)
            throw std::runtime_error("render: --samples: the range " + o.samples + " is empty");
    }

    render::ResolvedSettings rs;
    try {
        rs = render::resolve_settings(scene, ro);
    } catch (const std::invalid_argument& e) {
        throw std::runtime_error(std::string("render: ") + e.what());
    }
    if (o.explain) {
        print_explain(scene,
                      render::choose_kernel(scene.features(), rs.integrator, rs.max_depth,
                                            ro.force_general_kernel),
                      rs, ro.light_selection);
        if (o.outputs.empty()) return;
    }

    if (o.denoise) {
        render_denoised(scene, ro, rs, o);
        return;
    }
    if (!o.denoise_raw.empty() || !o.denoise_features.empty())
        throw std::runtime_error(std::string("render: ") +
                                 (o.denoise_raw.empty() ? "--denoise-features" : "--denoise-raw") +
                                 ": needs --denoise");
    render::RenderSession session(scene, ro);
    session.render();
    const render::Image image = session.image();
    for (const auto& out : o.outputs) {
        if (extension_of(out) == ".fpart")
            render::write_part(session.part(), out);
        else
            render::write_image(image, out);
    }
    if (!o.shadow_catcher_pass.empty())
        render::write_image(session.shadow_catcher_pass(), o.shadow_catcher_pass);
    report_render(scene, session.stats(), o);
}

// Texture cache use, --stats-json and the dropped-sample warning of a finished render.
void report_render(const render::Scene& scene, const render::RenderStats& st,
                   const RenderCmdOptions& o) {
    const render::TextureMemoryStats tm = scene.texture_memory();
    const double hit_rate =
        tm.hits + tm.misses > 0 ? double(tm.hits) / double(tm.hits + tm.misses) : 1.0;
    if (tm.paged_images > 0 && !o.quiet)
        std::fprintf(stderr,
                     "facet: render: texture cache: %zu images paged; %.1f MiB whole + %.1f MiB "
                     "tiles at most (of %.1f MiB); tile hit rate %.4f\n",
                     tm.paged_images, double(tm.whole_bytes) / 1048576.0,
                     double(tm.tile_peak) / 1048576.0, double(tm.limit) / 1048576.0, hit_rate);
    if (!o.stats_json.empty()) {
        nlohmann::json j{{"scene", scene.name()},
                         {"kernel", st.kernel.name},
                         {"integrator", render::integrator_name(st.kernel.integrator)},
                         {"seconds", st.seconds},
                         {"spp", st.spp},
                         {"mean_spp", st.mean_spp},
                         {"passes", st.passes},
                         {"threads", st.threads},
                         {"paths", st.paths},
                         {"rays", st.rays},
                         {"shadow_rays", st.shadow_rays},
                         {"nonfinite_samples", st.nonfinite},
                         {"paths_per_s", double(st.paths) / st.seconds},
                         {"rays_per_s", double(st.rays + st.shadow_rays) / st.seconds},
                         {"texture_memory",
                          {{"limit", tm.limit},
                           {"whole_bytes", tm.whole_bytes},
                           {"paged_images", tm.paged_images},
                           {"tile_capacity", tm.tile_capacity},
                           {"tile_peak", tm.tile_peak},
                           {"peak_bytes", tm.peak_bytes()},
                           {"hits", tm.hits},
                           {"misses", tm.misses},
                           {"evictions", tm.evictions},
                           {"hit_rate", hit_rate}}}};
        std::ofstream f(o.stats_json);
        if (!(f << j.dump(2) << "\n"))
            throw std::runtime_error("render: --stats-json " + o.stats_json + ": cannot write");
    }
    if (st.nonfinite > 0)
        std::fprintf(stderr,
                     "facet: render: warning: %llu samples were NaN/inf (or beyond 7e13) and were "
                     "dropped\n",
                     static_cast<unsigned long long>(st.nonfinite));
}

// --denoise: render::render_denoised (denoise.h) and its images.
void render_denoised(const render::Scene& scene, const render::RenderOptions& ro,
                     const render::ResolvedSettings& rs, const RenderCmdOptions& o) {
    for (const auto& out : o.outputs)
        if (extension_of(out) == ".fpart")
            throw std::runtime_error("render: --denoise: -o " + out +
                                     ": a part cannot be denoised (denoise after the merge)");
    render::DenoiseOptions dopt;
    dopt.threads = rs.threads;
    render::DenoisedRender r;
    try {
        r = render::render_denoised(scene, ro, dopt);
    } catch (const std::invalid_argument& e) {
        throw std::runtime_error(std::string("render: --") + e.what());
    }
    for (const auto& out : o.outputs) render::write_image(r.image, out);
    if (!o.denoise_raw.empty()) render::write_image(r.raw, o.denoise_raw);
    if (!o.denoise_features.empty()) {
        render::write_image(r.features.albedo, o.denoise_features + ".albedo.exr");
        render::write_image(r.features.normal, o.denoise_features + ".normal.exr");
        render::write_image(r.features.depth, o.denoise_features + ".depth.exr");
        render::write_image(r.features.albedo_variance,
                            o.denoise_features + ".albedo_variance.exr");
        render::write_image(r.features.normal_variance,
                            o.denoise_features + ".normal_variance.exr");
        render::write_image(r.features.depth_variance, o.denoise_features + ".depth_variance.exr");
    }
    report_render(scene, r.stats, o);
}

void check_pass_output(const std::string& path, const char* command) {
    const std::string e = extension_of(path);
    if (e != ".exr" && e != ".png")
        throw std::runtime_error(std::string(command) + ": --shadow-catcher-pass " + path +
                                 ": unknown image extension (use .exr or .png)");
}

void run_merge(const std::vector<std::string>& inputs, const std::vector<std::string>& outputs,
               const std::string& pass) {
    if (outputs.empty())
        throw std::runtime_error("merge: no output: give -o out.exr and/or -o out.png");
    for (const auto& out : outputs) {
        const std::string e = extension_of(out);
        if (e != ".exr" && e != ".png")
            throw std::runtime_error("merge: -o " + out +
                                     ": unknown image extension (use .exr or .png)");
    }
    if (!pass.empty()) check_pass_output(pass, "merge");
    std::vector<render::RenderPart> parts;
    for (const auto& in : inputs) parts.push_back(render::read_part(in));
    const render::Film film = render::merge_parts(parts, inputs);
    const render::Image image = film.resolve(!pass.empty());
    for (const auto& out : outputs) render::write_image(image, out);
    if (!pass.empty()) render::write_image(film.resolve_shadow_catcher_pass(), pass);
}

}  // namespace

void add_render_command(CLI::App& app) {
    auto o = std::make_shared<RenderCmdOptions>();
    CLI::App* cmd = app.add_subcommand("render", "Render a JSON scene (scenes/FORMAT.md)");
    cmd->add_option("scene", o->scene, "scene file (.json)")->required();
    cmd->add_option("-o,--output", o->outputs,
                    "output image; .exr = linear float, .png = 8-bit sRGB; repeatable")
        ->allow_extra_args(false);
    cmd->add_option("--spp", o->spp, "samples per pixel (default: the scene's)")
        ->check(CLI::PositiveNumber);
    cmd->add_option("--time", o->time_s,
                    "time budget in seconds: render in passes until it is spent (spp is a cap)")
        ->check(CLI::NonNegativeNumber);
    cmd->add_option("--threads", o->threads, "worker threads (0 = all cores)")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str();
    cmd->add_option("--integrator", o->integrator, "direct | path (default: the scene's)");
    cmd->add_option("--seed", o->seed, "sampler seed (default: the scene's)")
        ->check(CLI::NonNegativeNumber);
    cmd->add_option("--max-depth", o->max_depth, "maximum bounces (default: the scene's)")
        ->check(CLI::NonNegativeNumber);
    cmd->add_option("--kernel", o->kernel,
                    "auto: kernel specialised to the scene; general: the all-features kernel")
        ->check(CLI::IsMember({"auto", "general"}))
        ->capture_default_str();
    cmd->add_option("--light-selection", o->light_selection,
                    "path: choose the light for each shadow ray in proportion to its "
                    "contribution measured from the camera (view), to its power, uniformly, or "
                    "by the light tree (tree: per shaded point; for many lights); auto: tree "
                    "with 12 or more local lights, else view")
        ->check(CLI::IsMember({"auto", "view", "power", "uniform", "tree"}))
        ->capture_default_str();
    cmd->add_option("--sampler", o->sampler,
                    "sobol: Owen-scrambled Sobol samples; independent: independent uniform "
                    "samples (for comparisons: slower convergence)")
        ->check(CLI::IsMember({"sobol", "independent"}))
        ->capture_default_str();
    cmd->add_option("--texture-memory", o->texture_memory_mib,
                    "bound on texture memory in MiB (float texels, MIP levels included), at least "
                    "1; images past it are paged through a tile cache within it")
        ->capture_default_str();
    cmd->add_flag("--explain", o->explain,
                  "print the scene analysis and which kernel features were chosen and skipped");
    cmd->add_flag("-q,--quiet", o->quiet, "no progress output");
    cmd->add_option("--stats-json", o->stats_json, "write timing and ray counts as JSON");
    cmd->add_option("--region", o->region,
                    "render only the pixels [x0, x1) x [y0, y1) of the image: x0,y0,x1,y1");
    cmd->add_option("--samples", o->samples,
                    "render only samples [s0, s1) of every pixel (of the spp-sample render): "
                    "s0:s1; write the part with -o part.fpart and assemble with facet merge");
    cmd->add_option("--adaptive-threshold", o->adaptive_threshold,
                    "adaptive sampling: stop sampling a tile once its pixels' noise estimate "
                    "(Cycles' Noise Threshold measure) is below this in root mean square and "
                    "nowhere 4 times above, in [0, 1]; 0 = off (default: the scene's)")
        ->check(CLI::Range(0.0, 1.0));
    cmd->add_option("--adaptive-min-samples", o->adaptive_min_samples,
                    "adaptive sampling: samples every pixel takes first (0 = automatic, "
                    "max(16, ceil(2 / sqrt(threshold))); default: the scene's)")
        ->check(CLI::NonNegativeNumber);
    cmd->add_flag("--denoise", o->denoise,
                  "denoise the image (denoise.h: feature-guided, from two half-buffers and the "
                  "albedo, normal and depth AOVs and their per-pixel variances; no longer an "
                  "unbiased estimate)");
    cmd->add_option("--denoise-raw", o->denoise_raw,
                    "with --denoise: also write the image before denoising (.exr or .png)");
    cmd->add_option("--denoise-features", o->denoise_features,
                    "with --denoise: also write the features as PREFIX.albedo.exr, "
                    "PREFIX.normal.exr and PREFIX.depth.exr, and the variances of their means "
                    "as PREFIX.albedo_variance.exr, .normal_variance.exr, .depth_variance.exr");
    cmd->add_option("--shadow-catcher-pass", o->shadow_catcher_pass,
                    "also write the Shadow Catcher pass (.exr or .png; Cycles': the light the "
                    "shadow catchers kept, 1 where none is seen); the image is then Cycles' "
                    "Combined of such a render: the other objects without the catchers' shadows "
                    "(scenes/FORMAT.md, Shadow catchers)");
    cmd->callback([o] { run_render(*o); });

    auto inputs = std::make_shared<std::vector<std::string>>();
    auto outputs = std::make_shared<std::vector<std::string>>();
    auto pass = std::make_shared<std::string>();
    CLI::App* merge = app.add_subcommand(
        "merge", "Assemble render parts (.fpart from render --region/--samples) into the image");
    merge->add_option("parts", *inputs, "part files (.fpart)")->required();
    merge->add_option("-o,--output", *outputs, "output image (.exr or .png); repeatable")
        ->allow_extra_args(false);
    merge->add_option("--shadow-catcher-pass", *pass,
                      "also write the Shadow Catcher pass (as facet render's)");
    merge->callback([inputs, outputs, pass] { run_merge(*inputs, *outputs, *pass); });
}

}  // namespace facet::cli
