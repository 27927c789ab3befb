// POV-Ray 3.7 SDL export of a SceneDescription, for povray-facet (the patched POV-Ray of
// povray_patch/): the picture `facet render --integrator direct` renders of the same scene
// (docs/povray.md). `facet export-pov` and the Python module's facet.export_pov call it.
//
// Conventions: everything the SDL cannot express exactly is an error (SceneError
// "<name>: <JSON pointer>: <message>"), except what an option asks to approximate. The scene
// is validated by build_scene first: the SDL is only written for scenes `facet render`
// accepts. Each shape and light kind writes itself (kinds.h, `pov`).
//  - camera: explicit location/right/up/direction vectors in Facet's world coordinates, with
//    pixel centres as Facet's (scenes/FORMAT.md); `orthographic` with the window as right/up;
//    lens shift moves the location (orthographic) or the direction off axis (perspective),
//    exactly; a round thin lens of a perspective camera without shift becomes focal_blur
//    (aperture = 2 aperture_radius, focal_point on the axis at focus_distance: the same plane
//    of focus; POV-Ray's own aperture samples, blur_samples of them). Polygonal apertures,
//    orthographic focal blur and shift with focal blur are errors;
//  - `assumed_gamma 1.0`, `max_trace_level` = max_depth + 1 (the camera ray is level 0, so
//    max_depth mirror bounces are traced as Facet's direct integrator does), `adc_bailout 0`
//    (no ray dropped for low weight), no ambient; render with antialiasing off, EXR output;
//  - lights in povray-facet's `physical_falloff` (exact 1/d^2), colours from light_units.h;
//  - emitters (quads, meshes, discs with `emission`): the visible surface glows with
//    `emission` and casts no shadow, and its light is a set of cos-weighted spotlights, one
//    per cell of a midpoint (centroid) quadrature of the emitter, each with its own shadow
//    ray. Not POV-Ray's `area_light`: that shades with the average visibility of the grid
//    times the average unshadowed shading (trace.cpp ComputeFullAreaDiffuseLight), puts its
//    points on the light's edges, and its points are isotropic, where a Lambertian emitter's
//    intensity falls off as cos(theta);
//  - materials: `finish { brdf { ... } }` with the core's model and parameter names; the
//    pigment carries the diffuse reflectance (the patch's tinting rule); `samples` (glossy
//    reflection rays) is 0 unless glossy_samples says otherwise, since the direct integrator
//    traces none;
//  - textures: an image or checker as a material's diffuse colour (the pigment) or a shape's
//    emission is a `uv_mapping` pigment (image_map with the core's UV, wrap, filter, colour
//    space and UV transform), on objects whose POV-Ray UVs are the core's: mesh2 with
//    uv_vectors, spheres with their axes swapped (docs/povray.md, "Textures"). Every other
//    textured parameter, normal and bump maps are errors;
//  - media (scene max_depth 1 only: single scattering): a homogeneous medium is POV-Ray
//    `media` (absorption, Henyey-Greenstein scattering; no emission) inside its boundary's object,
//    or atmospheric media for the world medium; lights get media_attenuation; a `null`
//    boundary is a transmit-1 surface (docs/povray.md, "Media");
//  - radiosity: a `radiosity {}` block; emitters are then `no_radiosity` with a black twin that
//    only radiosity rays see, because the cell lights already count their light.
#pragma once

#include <string>

#include "facet/render/scene_description.h"

namespace facet::render {

struct PovExportOptions {
    // Emitter quadrature: N x N cells per parallelogram quad, N^2 per triangle, N rings x 4N
    // sectors per disc; each cell is one POV-Ray light. In [1, 64].
    int area_grid = 8;
    // Glossy reflection rays per hit of brdf finishes (POV `samples`), in [0, 10000].
    int glossy_samples = 0;
    // Camera rays per pixel of a thin-lens camera's focal_blur (POV `blur_samples`), in
    // [1, 4096]: POV-Ray's own aperture sampling, an approximation of the lens average.
    int blur_samples = 64;
    // "error": an environment light is an error; "background": exported as the background
    // only (it then lights no surface: an approximation); "light": a sky_sphere that brdf
    // finishes importance-sample (povray-facet's `brdf_sky_sampling`, docs/povray.md).
    std::string environment = "error";
    // With environment "light": sky samples per camera-ray hit (`brdf_sky_sampling N`; 1 at
    // deeper hits), in [1, 4096].
    int sky_samples = 16;
    // POV-Ray radiosity for the indirect light (approximates `--integrator path`): "off",
    // "low" (50,1.0,4), "medium" (200,0.4,8), "high" (800,0.15,16) or
    // "COUNT,ERROR_BOUND,RECURSION_LIMIT".
    std::string radiosity = "off";
    // Image textures with the `mipmap` filter (the scene format's default): "error", or
    // "linear": written as POV-Ray's bilinear lookup of the full image (`interpolate 2`), which
    // is the core's mipmap wherever the texture is magnified (MIP level <= 0) and sharper where
    // it is minified (an approximation; docs/povray.md).
    std::string mipmap = "error";
    // Media: POV-Ray `intervals` per medium along a ray (equal steps, two samples each), in
    // [1, 200] (POV-Ray holds at most 256 per ray): exact for absorption, a quadrature
    // of the lit scattering.
    int media_intervals = 128;
};

// Checks the options alone (throws std::invalid_argument naming the option).
void check_pov_options(const PovExportOptions& options);

// The SDL text. `name` prefixes errors (a file name, "python", ...).
std::string export_pov(const SceneDescription& desc, const std::string& name,
                       const PovExportOptions& options = {});

// Writes the SDL to `path`, and with a non-empty `ini_path` a POV-Ray .ini (size, no
// antialiasing, 32-bit float EXR output). Throws SceneError (scene) or std::runtime_error
// (files).
void export_pov_file(const SceneDescription& desc, const std::string& name, const std::string& path,
                     const PovExportOptions& options = {}, const std::string& ini_path = "");

}  // namespace facet::render
