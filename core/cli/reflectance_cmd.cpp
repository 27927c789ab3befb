// `facet reflectance`: the reflectances of Cohen & Wallace table 2.2 by deterministic quadrature.
#include <fmt/format.h>
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <cstdio>
#include <memory>

#include "commands.h"
#include "facet/reflectance.h"
#include "facet/registry.h"
#include "model_args.h"

namespace facet::cli {

namespace {

struct ReflectanceOptions {
    std::string model;
    double theta_i = 0.0, phi_i = 0.0;
    bool table = false, bihemispherical = false, json = false;
    std::string thetas = "0,15,30,45,60,75,85,89";
    std::string sweep;  // "alpha=0.05,0.1,0.2" : a roughness (or any number) parameter sweep
    std::string cone_in, cone_out;  // "theta,phi,half_angle" in degrees
    int order = 0;                  // 0: adaptive to --tolerance; > 0: fixed Gauss-Legendre order
    double tolerance = 1e-6;        // absolute, per channel
};

nlohmann::json rgb_json(const DVec3& c) {
    return {c.r, c.g, c.b};
}

double max_error(const Reflectance& r) {
    return std::max(r.error.r, std::max(r.error.g, r.error.b));
}

Cone parse_cone(const std::string& text, const std::string& flag) {
    auto v = parse_numbers(text, flag);
    if (v.size() != 3)
        throw std::runtime_error(flag + ": expected theta,phi,half_angle in degrees");
    if (!(v[2] > 0.0 && v[2] <= 90.0))
        throw std::runtime_error(flag + ": half_angle must be in (0, 90] degrees");
    const double deg = kPiD / 180.0;
    return {spherical_direction(float(v[0] * deg), float(v[1] * deg)), float(v[2] * deg)};
}

void run(const ReflectanceOptions& o, std::vector<std::string> extras) {
    if (o.order != 0 && (o.order < 2 || o.order > 512))
        throw std::runtime_error("--order: must be in [2, 512]");
    if (!(o.tolerance >= 1e-9 && o.tolerance <= 1e-1))
        throw std::runtime_error(
            "--tolerance: must be in [1e-9, 0.1] (the BxDFs evaluate in float: below ~1e-7 "
            "round-off dominates)");
    // A model that transmits: reflectance and transmittance apart, for one incidence
    // (directional_scattering); the other reflectances integrate the upper hemisphere only.
    const bool transmissive =
        find_model(o.model) && material_from_args(o.model, extras).transmissive();
    if (transmissive && (o.table || o.bihemispherical || !o.cone_in.empty() || !o.cone_out.empty()))
        throw std::runtime_error("--model " + o.model +
                                 ": a transmissive material has reflectance and transmittance "
                                 "for one incidence only (--theta-i), not --table, "
                                 "--bihemispherical or cones");
    if (transmissive) {
        if (!(o.theta_i >= 0.0 && o.theta_i <= 180.0))
            throw std::runtime_error(
                "--theta-i: must be in [0, 180] degrees for a transmissive model (above 90: "
                "from inside)");
        if (o.order != 0)
            throw std::runtime_error(
                "--order: a transmissive model's scattering is a fixed "
                "midpoint rule over its sampler; leave --order out");
        const double deg = kPiD / 180.0;
        const Material m = material_from_args(o.model, extras);
        const Scattering s = directional_scattering(
            m, spherical_direction(float(o.theta_i * deg), float(o.phi_i * deg)));
        if (o.json) {
            std::puts(nlohmann::json{{"theta_i", o.theta_i},
                                     {"rho", rgb_json(s.reflected.value)},
                                     {"error", rgb_json(s.reflected.error)},
                                     {"tau", rgb_json(s.transmitted.value)},
                                     {"tau_error", rgb_json(s.transmitted.error)}}
                          .dump(2)
                          .c_str());
        } else {
            const DVec3& r = s.reflected.value;
            const DVec3& t = s.transmitted.value;
            fmt::print(
                "rho(wi->same side) at theta_i = {} deg: {:.8f} {:.8f} {:.8f}   (estimated "
                "error {:.1e})\n"
                "tau(wi->other side) at theta_i = {} deg: {:.8f} {:.8f} {:.8f}   (estimated "
                "error {:.1e})\n",
                o.theta_i, r.r, r.g, r.b, max_error(s.reflected), o.theta_i, t.r, t.g, t.b,
                max_error(s.transmitted));
        }
        return;
    }
    QuadratureSettings settings;
    settings.tolerance = o.tolerance;
    const bool fixed = o.order != 0;
    auto directional = [&](const Material& m, const Vec3& wi) {
        return fixed ? directional_hemispherical(m, wi, o.order)
                     : directional_hemispherical(m, wi, settings);
    };
    // Warn on stderr when refinement stopped before reaching the tolerance.
    auto check = [&](const Reflectance& r) {
        if (!fixed && max_error(r) > o.tolerance)
            fmt::print(stderr,
                       "warning: error estimate {:.1e} above --tolerance {:.1e} (evaluation "
                       "budget spent)\n",
                       max_error(r), o.tolerance);
    };
    const double deg = kPiD / 180.0;
    if (o.bihemispherical) {
        Material m = material_from_args(o.model, extras);
        Reflectance r =
            fixed ? bihemispherical(m, std::min(o.order, 32)) : bihemispherical(m, settings);
        check(r);
        if (o.json)
            std::puts(
                nlohmann::json{{"bihemispherical", rgb_json(r.value)}, {"error", rgb_json(r.error)}}
                    .dump(2)
                    .c_str());
        else
            fmt::print(
                "rho(2pi->2pi) = {:.8f} {:.8f} {:.8f}   (estimated quadrature error {:.1e})\n",
                r.value.r, r.value.g, r.value.b, max_error(r));
        return;
    }
    if (!o.cone_in.empty() || !o.cone_out.empty()) {
        if (o.cone_in.empty() || o.cone_out.empty())
            throw std::runtime_error("--cone-in and --cone-out go together");
        Material m = material_from_args(o.model, extras);
        Reflectance r =
            biconical(m, parse_cone(o.cone_in, "--cone-in"), parse_cone(o.cone_out, "--cone-out"),
                      fixed ? std::min(o.order, 24) : 24);
        if (o.json)
            std::puts(nlohmann::json{{"biconical", rgb_json(r.value)}, {"error", rgb_json(r.error)}}
                          .dump(2)
                          .c_str());
        else
            fmt::print(
                "rho(cone_in->cone_out) = {:.8f} {:.8f} {:.8f}   (estimated quadrature error "
                "{:.1e}, fixed order 24)\n",
                r.value.r, r.value.g, r.value.b, max_error(r));
        return;
    }
    if (!o.table) {
        if (!(o.theta_i >= 0.0 && o.theta_i <= 90.0))
            throw std::runtime_error("--theta-i: must be in [0, 90] degrees");
        Material m = material_from_args(o.model, extras);
        Vec3 wi = spherical_direction(float(o.theta_i * deg), float(o.phi_i * deg));
        Reflectance r = directional(m, wi);
        check(r);
        if (o.json)
            std::puts(nlohmann::json{
                {"theta_i", o.theta_i}, {"rho", rgb_json(r.value)}, {"error", rgb_json(r.error)}}
                          .dump(2)
                          .c_str());
        else
            fmt::print(
                "rho(wi->2pi) at theta_i = {} deg: {:.8f} {:.8f} {:.8f}   (estimated quadrature "
                "error {:.1e})\n",
                o.theta_i, r.value.r, r.value.g, r.value.b, max_error(r));
        return;
    }
    // Table over theta_i (rows) and a parameter sweep (columns), luminance of rho.
    std::vector<double> thetas = parse_numbers(o.thetas, "--thetas");
    std::string pname;
    std::vector<double> values;
    if (!o.sweep.empty()) {
        size_t eq = o.sweep.find('=');
        if (eq == std::string::npos) throw std::runtime_error("--sweep: expected name=v1,v2,...");
        pname = o.sweep.substr(0, eq);
        values = parse_numbers(o.sweep.substr(eq + 1), "--sweep");
    }
    std::vector<std::string> column_names;
    std::vector<Material> materials;
    if (values.empty()) {
        materials.push_back(material_from_args(o.model, extras));
        column_names.push_back(o.model);
    }
    for (double v : values) {
        std::vector<std::string> e = extras;
        e.push_back("--" + pname);
        e.push_back(fmt::format("{}", v));
        materials.push_back(material_from_args(o.model, e));
        column_names.push_back(fmt::format("{}={}", pname, v));
    }
    nlohmann::json rows = nlohmann::json::array();
    if (!o.json) {
        fmt::print("rho(wi->2pi), luminance; model {}\n{:>8}", o.model, "theta_i");
        for (const auto& n : column_names) fmt::print(" {:>14}", n);
        fmt::print("\n");
    }
    for (double t : thetas) {
        if (!(t >= 0.0 && t <= 90.0))
            throw std::runtime_error("--thetas: angles must be in [0, 90]");
        Vec3 wi = spherical_direction(float(t * deg), float(o.phi_i * deg));
        nlohmann::json row{{"theta_i", t}};
        if (!o.json) fmt::print("{:8.2f}", t);
        for (size_t k = 0; k < materials.size(); ++k) {
            Reflectance r = directional(materials[k], wi);
            check(r);
            row[column_names[k]] = rgb_json(r.value);
            row[column_names[k] + " error"] = rgb_json(r.error);
            if (!o.json) fmt::print(" {:14.8f}", luminance(Rgb(r.value)));
        }
        if (!o.json) fmt::print("\n");
        rows.push_back(row);
    }
    if (o.json) std::puts(rows.dump(2).c_str());
}

}  // namespace

void add_reflectance_command(CLI::App& app) {
    auto o = std::make_shared<ReflectanceOptions>();
    CLI::App* cmd = app.add_subcommand(
        "reflectance",
        "directional-hemispherical, bihemispherical and biconical reflectances; reflectance "
        "and transmittance of transmissive models");
    cmd->add_option("--model", o->model, "model name (see `facet brdf models`)")->required();
    cmd->add_option("--theta-i", o->theta_i,
                    "incidence angle, degrees (transmissive models: above 90 from inside)")
        ->capture_default_str();
    cmd->add_option("--phi-i", o->phi_i, "incidence azimuth, degrees")->capture_default_str();
    cmd->add_flag("--table", o->table, "table over --thetas (rows) and --sweep (columns)");
    cmd->add_option("--thetas", o->thetas, "incidence angles of the table, degrees")
        ->capture_default_str();
    cmd->add_option("--sweep", o->sweep, "parameter sweep for the table, e.g. alpha=0.05,0.1,0.3");
    cmd->add_flag("--bihemispherical", o->bihemispherical, "rho(2pi -> 2pi)");
    cmd->add_option("--cone-in", o->cone_in, "biconical: incident cone theta,phi,half_angle (deg)");
    cmd->add_option("--cone-out", o->cone_out,
                    "biconical: reflected cone theta,phi,half_angle (deg)");
    cmd->add_option("--tolerance", o->tolerance,
                    "target absolute quadrature error per channel (adaptive cubature)")
        ->capture_default_str();
    cmd->add_option("--order", o->order,
                    "fixed Gauss-Legendre order per dimension instead of --tolerance (error from "
                    "order vs 2x order); biconical always uses a fixed order (24)");
    cmd->add_flag("--json", o->json, "JSON output");
    cmd->allow_extras();
    cmd->footer("Model parameters are passed as --name value (see `facet brdf models`).");
    cmd->callback([o, cmd] { run(*o, cmd->remaining()); });
}

}  // namespace facet::cli
