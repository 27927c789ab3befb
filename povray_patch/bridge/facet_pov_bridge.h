// The bridge between POV-Ray and the Facet core: the only Facet code POV-Ray's sources call.
//
// This header includes no Facet and no POV-Ray header (POV-Ray's frame.h defines the macros X,
// Y, Z and EPSILON, which would break the core's headers), and it uses plain doubles and floats
// only. The bridge owns every Brdf it builds for the life of the process: a FINISH (malloc'ed
// and struct-copied by POV-Ray) just holds the pointer.
//
// Directions are world-space unit vectors. `n` is the shading normal on the side of the
// viewer, `wo` points to the viewer, `wi` to the light; all point away from the surface.
#pragma once

#include <string>
#include <vector>

namespace facet_pov {

class Brdf;

// ---- parsing: `finish { brdf { MODEL PARAM VALUE ... } }` ----------------------------------

enum class ParamKind { Number, Colour, Word, Bool, Unknown };

// "'lambert', 'mirror', 'ggx', ..." (every model of the core's registry, in its order).
std::string model_list();
bool is_model(const char* name);
// The kind of `param` of `model`; Unknown with `message` set ("unknown parameter 'x' for model
// 'ggx' (did you mean 'alpha'?)") when the model has no such parameter.
ParamKind param_kind(const char* model, const char* param, std::string& message);
// The allowed bare words of a Word parameter ("'none', 'dielectric', ..."), or "" if open.
std::string word_choices(const char* model, const char* param);

// Collects the parameters of one block; build() validates them with the core's registry.
class BrdfBuilder {
  public:
    explicit BrdfBuilder(const char* model);
    ~BrdfBuilder();
    BrdfBuilder(const BrdfBuilder&) = delete;
    BrdfBuilder& operator=(const BrdfBuilder&) = delete;

    // false if the parameter was given already (the parser reports it).
    bool set_number(const char* name, double v);
    bool set_colour(const char* name, double r, double g, double b);
    bool set_word(const char* name, const char* word);
    bool set_bool(const char* name, bool v);
    // POV-Ray's own parameter of the block (not a core parameter): glossy rays per hit; 0
    // turns the glossy reflection of other objects off (the lobe still shades the lights).
    void set_glossy_samples(int n);
    // The validated BRDF, or nullptr with `message` set to the registry's error
    // ("parameter 'alpha' of model 'ggx': must be in [0, 10] (got 12)"); `param` names the
    // offending parameter ("" for the model).
    const Brdf* build(std::string& message, std::string& param);

  private:
    struct Impl;
    Impl* m_impl;
};

// ---- brdf_convert_classic: a classic finish as a brdf (facet/pov_classic.h) -------------

// POV-Ray's FINISH fields as POV-Ray stores them (Roughness is 1 / roughness there), and the
// object's interior IOR over the atmosphere's (1 without an interior).
struct ClassicFinish {
    double diffuse, diffuse_back, brilliance;
    double phong, phong_size, specular, specular_exponent, metallic;
    double reflection_min[3], reflection_max[3];
    bool reflection_fresnel;
    double reflection_falloff, reflection_exponent, ior, irid, crand;
    bool subsurface;
};

// One approximation or dropped term of a conversion: `approximated` false means reported
// (dropped or kept classic); `kind` is a short fixed text ("brilliance", "irid (dropped)").
struct ClassicNote {
    bool approximated;
    std::string kind;
};

// The brdf of a classic finish: Lambert (rho = diffuse, tinted by the pigment, taking what the
// specular lobes leave), one blinn lobe for phong and specular (tinted by `metallic` as POV-Ray
// tints its highlights, glossy_tint), mirror lobes for reflection. nullptr when the finish
// stays classic (subsurface); `notes` say what is not exact.
const Brdf* convert_classic(const ClassicFinish& finish, std::vector<ClassicNote>& notes);
// A converted finish's blinn lobe as it reflects other objects on the mirror ray (with a
// mirror lobe: facet::pov::ClassicConversion::glossy_folded): its albedo at wo, tinted by its
// `metallic` at the mirror angle; 0 for anything else. Added to mirror_weight's.
void folded_glossy_weight(const Brdf* b, const double n[3], const double wo[3],
                          const float pigment[3], float out[3]);
// A stable copy of `text` for the life of the process (file names in POV-Ray's FINISH).
const char* intern(const char* text);
// True for a Brdf made by convert_classic (POV-Ray's reflection `metallic` tint applies).
bool is_converted(const Brdf* b);
// The factor of the glossy lobe toward wi for a pigment (POV-Ray's `metallic` tint; 1 for a
// brdf block): multiplies the glossy rays' weights (shade() applies it to lights itself).
void glossy_tint(const Brdf* b, const double n[3], const double wi[3], const float pigment[3],
                 float out[3]);

// ---- shading -------------------------------------------------------------------------------

// What a Brdf has: lobes that lights shade (diffuse/glossy), a glossy lobe, a mirror lobe.
// For principled (reflection part) these are the core model's lobes grouped by how POV-Ray
// estimates them: "diffuse" the cosine lobe (Disney diffuse + sheen), "glossy" the rough
// specular and clearcoat, "mirror" the delta ones (facet::PrincipledBxDF::only); its colours
// are its own parameters and the pigment (`tint`) does not enter. oren_nayar is a diffuse lobe
// tinted by the pigment as lambert is (facet_pov_bridge.cpp, class Brdf).
bool lit_by_lights(const Brdf* b);
bool has_glossy(const Brdf* b);
bool has_mirror(const Brdf* b);

// The light reflected toward wo per unit light colour: pi * f(wo, wi) * cos(theta_i), with the
// diffuse part tinted by `tint` (the pigment). POV-Ray's classic `diffuse d` gives d * cos per
// unit light colour, so the factor pi makes a Lambert reflectance rho equal `diffuse rho`.
// `glossy` false leaves the glossy lobe out (radiosity rays). Writes 0 when wo or wi is below.
void shade(const Brdf* b, const double n[3], const double wo[3], const double wi[3],
           const float tint[3], bool glossy, float out[3]);

// Directional-hemispherical reflectance of the diffuse lobe at wo (with its energy-sharing
// weight), tinted: what radiosity and photons multiply the incoming irradiance by.
void diffuse_albedo(const Brdf* b, const double n[3], const double wo[3], const float tint[3],
                    float out[3]);

// Weight of the mirror lobe at wo (scale times the core's Fresnel at the angle of wo).
void mirror_weight(const Brdf* b, const double n[3], const double wo[3], float out[3]);

// Solid-angle density with which sample_glossy returns wi (0 without a glossy lobe or below
// the surface): the BRDF side of the sky sampling's multiple importance sampling.
double glossy_pdf(const Brdf* b, const double n[3], const double wo[3], const double wi[3]);

// One importance sample of the glossy lobe: writes wi and the weight f cos / pdf (glossy lobe
// alone, so the weights of the glossy rays average to the lobe's albedo). false when the lobe
// gives no sample (below the surface, zero albedo). u[0] picks a sub-lobe (energy
// compensation), u[1], u[2] drive the warp; all in [0, 1).
bool sample_glossy(const Brdf* b, const double n[3], const double wo[3], const double u[3],
                   double wi[3], float weight[3]);

// Glossy reflection rays traced at one hit: the block's `samples` (default 8) at the first
// hit of a camera ray (trace level 1), 1 at deeper hits (so that the cost stays linear in
// the trace depth); 0 for `samples 0` and for lobes that are a mirror or absent.
int glossy_ray_count(const Brdf* b, unsigned trace_level);

// Sample `index` of the `count` glossy samples of one hit: the renderer's Owen-scrambled Sobol
// point (facet/render/sampler.h) of the sequence seeded by (seed, trace_level), deterministic
// in its arguments (no per-thread state, so the image does not depend on the thread count).
void glossy_sample(unsigned seed, unsigned trace_level, int index, int count, double u[3]);

// A 32-bit hash of pixel coordinates and sample number, for TraceTicket::facetSeed.
unsigned pixel_seed(double x, double y, unsigned sample);

}  // namespace facet_pov
