// `facet convert in.exr -o out.pfm`: re-encode an image (.exr/.png in; .exr/.png/.pfm out) —
// PFM (float32, exact) is for scripts that read pixels without an EXR library (the POV-Ray
// cross-check).
// `facet diff a.exr b.exr`: compare a test image with a reference (metrics in
// facet/render/diff.h). Exit code 0 when the comparison ran (and, with --require, when enough
// pixels are within tolerance), 2 when --require is not met, 1 on errors (unreadable files,
// mismatched sizes).
#include <fmt/format.h>
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <cctype>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <string>

#include "commands.h"
#include "facet/render/diff.h"
#include "facet/render/image.h"

namespace facet::cli {

namespace {

struct DiffOptions {
    std::string a, b;
    double tolerance = 1e-2;
    double abs_tolerance = 0.0;
    std::string heatmap;
    bool json = false;
    double require = -1.0;
};

void run_diff(const DiffOptions& o) {
    using namespace facet::render;
    const Image a = read_image(o.a);
    const Image b = read_image(o.b);
    if (a.width() != b.width() || a.height() != b.height())
        throw std::runtime_error(fmt::format("diff: {} is {}x{} but {} is {}x{}", o.a, a.width(),
                                             a.height(), o.b, b.width(), b.height()));
    const DiffTolerance tol{o.tolerance, o.abs_tolerance};
    const DiffStats s = diff_images(a, b, tol);
    if (!o.heatmap.empty()) write_image(error_heatmap(a, b, tol), o.heatmap);
    if (o.json) {
        nlohmann::json j{{"a", o.a},
                         {"b", o.b},
                         {"width", s.width},
                         {"height", s.height},
                         {"rmse", s.rmse},
                         {"rel_mse", s.rel_mse},
                         {"max_abs", s.max_abs},
                         {"max_abs_pixel", {s.max_abs_x, s.max_abs_y}},
                         {"max_rel", s.max_rel},
                         {"mean_a", s.mean_a},
                         {"mean_b", s.mean_b},
                         {"tolerance", o.tolerance},
                         {"abs_tolerance", o.abs_tolerance},
                         {"fraction_within", s.fraction_within},
                         {"pixels_within", s.pixels_within},
                         {"nonfinite_pixels", s.nonfinite_pixels}};
        std::puts(j.dump(2).c_str());
    } else {
        fmt::print("{} vs {} ({}x{})\n", o.a, o.b, s.width, s.height);
        fmt::print("  RMSE              {:.6g}\n", s.rmse);
        fmt::print("  relative MSE      {:.6g}\n", s.rel_mse);
        fmt::print("  max abs error     {:.6g} at pixel ({}, {})\n", s.max_abs, s.max_abs_x,
                   s.max_abs_y);
        fmt::print("  max rel error     {:.6g}\n", s.max_rel);
        fmt::print("  mean a / mean b   {:.6g} / {:.6g}\n", s.mean_a, s.mean_b);
        fmt::print("  within tolerance  {:.4f}% of pixels (rel {:g}, abs {:g})\n",
                   100.0 * s.fraction_within, o.tolerance, o.abs_tolerance);
        if (s.nonfinite_pixels) fmt::print("  non-finite pixels {}\n", s.nonfinite_pixels);
    }
    std::fflush(stdout);
    if (o.require >= 0.0 && s.fraction_within < o.require) {
        std::fprintf(stderr,
                     "facet: diff: only %.4f%% of pixels within tolerance, %.4f%% required\n",
                     100.0 * s.fraction_within, 100.0 * o.require);
        throw CLI::RuntimeError(2);
    }
}

// Portable Float Map: "PF", width height, -1 (little endian), rows bottom to top, RGB float32.
void write_pfm(const render::Image& image, const std::string& path) {
    std::FILE* f = std::fopen(path.c_str(), "wb");
    if (!f) throw std::runtime_error("convert: -o " + path + ": cannot write");
    std::fprintf(f, "PF\n%d %d\n-1.0\n", image.width(), image.height());
    bool ok = true;
    for (int y = image.height() - 1; y >= 0; --y)
        for (int x = 0; x < image.width(); ++x) {
            const Rgb& p = image.at(x, y);
            const float v[3] = {p.r, p.g, p.b};  // x86/ARM: little endian, as "-1.0" says
            ok = ok && std::fwrite(v, sizeof(float), 3, f) == 3;
        }
    ok = (std::fclose(f) == 0) && ok;
    if (!ok) throw std::runtime_error("convert: -o " + path + ": cannot write");
}

void run_convert(const std::string& in, const std::string& out) {
    const render::Image image = render::read_image(in);
    const auto dot = out.find_last_of('.');
    std::string ext = dot == std::string::npos ? "" : out.substr(dot);
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    if (ext == ".pfm") {
        if (image.has_alpha())
            std::fprintf(stderr,
                         "facet: convert: warning: %s: PFM has no alpha channel; %s's "
                         "alpha is not written\n",
                         out.c_str(), in.c_str());
        write_pfm(image, out);
    } else
        render::write_image(image, out);
}

}  // namespace

void add_diff_command(CLI::App& app) {
    auto conv_in = std::make_shared<std::string>();
    auto conv_out = std::make_shared<std::string>();
    CLI::App* conv = app.add_subcommand(
        "convert", "Re-encode an image: .exr/.png in; .exr (float), .png (sRGB) or .pfm out");
    conv->add_option("input", *conv_in, "input image (.exr or .png)")->required();
    conv->add_option("-o,--output", *conv_out, "output image (.exr, .png or .pfm)")->required();
    conv->callback([conv_in, conv_out] { run_convert(*conv_in, *conv_out); });

    auto o = std::make_shared<DiffOptions>();
    CLI::App* cmd =
        app.add_subcommand("diff",
                           "Compare a test image with a reference: RMSE, relative MSE, max errors, "
                           "fraction of pixels within tolerance, optional heat map");
    cmd->add_option("a", o->a, "test image (.exr or .png)")->required();
    cmd->add_option("b", o->b, "reference image (.exr or .png)")->required();
    cmd->add_option("--tolerance,-t", o->tolerance,
                    "relative tolerance per channel: |a-b| <= max(T |b|, abs)")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str();
    cmd->add_option("--abs-tolerance", o->abs_tolerance, "absolute tolerance floor per channel")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str();
    cmd->add_option("--heatmap", o->heatmap, "write an error heat map (.png or .exr)");
    cmd->add_flag("--json", o->json, "print the metrics as JSON");
    cmd->add_option("--require", o->require,
                    "exit with code 2 unless at least this fraction (0..1) of pixels is within "
                    "tolerance")
        ->check(CLI::Range(0.0, 1.0));
    cmd->callback([o] { run_diff(*o); });
}

}  // namespace facet::cli
