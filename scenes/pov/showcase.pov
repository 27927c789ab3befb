// scenes/showcase.json written by hand in POV-Ray SDL for povray-facet (until `facet
// export-pov` exists): the same camera (explicit vectors, scenes/FORMAT.md "POV-Ray export"),
// shapes and materials as `brdf` finishes. Approximations, since POV-Ray has no emitting
// quad: the softbox is a 6x5 area light with physical_falloff whose colour L A / pi (quad
// radiance L times area A, over pi for povray-facet's pi f cos scale) gives the quad's
// irradiance below it (no emitter cosine), plus a visible emitting polygon (hidden from
// reflections, see below). The environment, Blender's studio HDRI (CC0, Greg Zaal; installed
// with Debian's blender package), is the sky_sphere that `facet export-pov --environment light`
// writes for it: the same image_map and orientation matrix, lighting the brdf finishes through
// povray-facet's `brdf_sky_sampling` (docs/povray.md "Sky light"; no radiosity). The floor's
// tiles are the same image (scenes/textures/showcase_tiles.png, made by
// tools/make_showcase_texture.py) mapped as Facet maps a plane: u = x, v = -z in scene units, the
// image repeating every 4 units (uv_scale 0.25). The brushed sphere's anisotropy axis is the
// core's default tangent frame (POV-Ray has no surface tangents).
//
// The glass sphere (Facet's smooth `dielectric`, ior 1.5) is POV-Ray's own refraction: a
// filtering pigment, Fresnel reflection and an interior with the same ior (povray-facet's brdf
// finish is reflection only). Approximate: POV-Ray lets shadow rays through a filtering object
// (a tinted shadow, no caustic) where Facet's glass blocks them (its caustic arrives by BSDF
// sampling), and it does not scale radiance by 1/eta^2 inside (the two crossings cancel). The
// satin sphere is the principled model's reflection part (clearcoat + sheen) as a brdf finish.
//
// Declare=Classic=1 renders the same scene with stock POV-Ray finishes (phong, specular,
// reflection, metallic) for the side-by-side picture; that variant runs on the stock povray
// (without brdf_sky_sampling the sky only shows in reflections there). Sky_Samples sets the sky
// samples per camera-ray hit.
#version 3.7;
#ifndef (Classic) #declare Classic = 0; #end
#ifndef (Glossy_Samples) #declare Glossy_Samples = 8; #end
#ifndef (Sky_Samples) #declare Sky_Samples = 16; #end

global_settings {
  assumed_gamma 1.0 max_trace_level 12 ambient_light 0
  #if (!Classic) brdf_sky_sampling Sky_Samples #end
}

// camera: position, look_at, up, fov 36 (vertical), 960x540, pixel centres as Facet's
#declare P = <0, 1.8, 6.5>;
#declare F = vnormalize(<0, 0.55, 0> - P);
#declare R = vnormalize(vcross(F, <0, 1, 0>));
#declare U = vcross(R, F);
#declare Ty = tan(radians(36) / 2);
#declare Tx = Ty * image_width / image_height;
camera {
  perspective
  location P
  right 2 * Tx * R
  up 2 * Ty * U
  direction F  // POV-Ray 3.7 traces pixel centres itself (scenes/FORMAT.md)
}

// The studio HDRI as `facet export-pov --environment light` writes it for the JSON's light
// (up +y, rotated 90 degrees about +y; the matrix's 6e-17 round-off written as 0).
sky_sphere {
  pigment { image_map { exr "/usr/share/blender/datafiles/studiolights/world/studio.exr" map_type 1 interpolate 2 }
    matrix <0, 0, 1, 0, 1, 0, -1, 0, 0, 0, 0, 0> }
}

// softbox: quad (-1.5..1.5, 4, -1..1.5), radiance <9, 8.6, 8>, area 7.5
// (stock POV-Ray has no exact inverse square: fade_distance 1 fade_power 2 gives 2 / (1 + d^2),
// about twice 1 / d^2 at these distances, so the classic variant halves the colour)
light_source {
  <0, 4, 0.25> color rgb <9, 8.6, 8> * 7.5 / pi #if (Classic) / 2 #end
  area_light <3, 0, 0>, <0, 0, 2.5>, 6, 5 adaptive 1
  #if (Classic) fade_distance 1 fade_power 2 #else physical_falloff #end
}
// The visible softbox. no_reflection: the light source already gives every glossy highlight
// directly, so glossy rays must not see the emitter again (the mirror then does not show it).
polygon { 5, <-1.5, 4, -1>, <1.5, 4, -1>, <1.5, 4, 1.5>, <-1.5, 4, 1.5>, <-1.5, 4, -1>
  pigment { rgb <9, 8.6, 8> } finish { ambient 0 diffuse 0 emission 1 } no_shadow no_reflection }

#if (Classic)
  #declare Floor   = finish { ambient 0 diffuse 1 }
  #declare Clay    = finish { ambient 0 diffuse 1 }
  #declare Gold    = finish { ambient 0 diffuse 0.1 specular 0.8 roughness 0.01 metallic reflection { 0.6 metallic } }
  #declare Chrome  = finish { ambient 0 diffuse 0 reflection 0.6 }
  #declare Plastic = finish { ambient 0 diffuse 1 phong 0.6 phong_size 80 reflection { 0.02, 0.3 falloff 5 } }
  #declare Brushed = finish { ambient 0 diffuse 0.2 specular 0.6 roughness 0.05 metallic reflection { 0.4 metallic } }
  #declare Satin   = finish { ambient 0 diffuse 0.8 specular 0.5 roughness 0.01 reflection { 0.02, 0.2 falloff 5 } }
#else
  #declare Floor   = finish { ambient 0 brdf { lambert } }
  #declare Clay    = finish { ambient 0 brdf { lambert } }
  #declare Gold    = finish { ambient 0 brdf { ggx alpha 0.15 fresnel conductor eta rgb <0.143, 0.374, 1.442> k rgb <3.983, 2.385, 1.603> samples Glossy_Samples } }
  #declare Chrome  = finish { ambient 0 brdf { mirror fresnel conductor eta rgb <3.1, 3.1, 2.3> k rgb <3.3, 3.3, 3.1> } }
  #declare Plastic = finish { ambient 0 brdf { composite glossy_reflectance 1 distribution ggx alpha 0.08 fresnel dielectric ior 1.5 samples Glossy_Samples } }
  #declare Brushed = finish { ambient 0 brdf { ggx alpha_u 0.05 alpha_v 0.35 fresnel conductor samples Glossy_Samples } }
  #declare Satin   = finish { ambient 0 brdf { principled base_color rgb <0.55, 0.07, 0.2> roughness 0.5 sheen 1 sheen_tint 0.5 clearcoat 1 clearcoat_roughness 0.1 samples Glossy_Samples } }
#end
// Glass in both variants: classic POV-Ray refraction and Fresnel reflection.
#declare Glass = finish { ambient 0 diffuse 0 reflection { 0, 1 fresnel on } conserve_energy }

// The image maps [0, 1]^2 of the x-y plane; rotate -90*x takes (a, b) to (a, 0, -b), and
// scale 4 repeats it every 4 units: u' = x / 4, v' = -z / 4, as Facet's plane with uv_scale 0.25.
plane { y, 0
  pigment { image_map { png "../textures/showcase_tiles.png" interpolate 2 } rotate -90 * x scale 4 }
  finish { Floor } }
sphere { <-2.3, 0.5, -0.6>, 0.5 pigment { rgb <0.7, 0.25, 0.15> } finish { Clay } }
sphere { <-0.9, 0.6, 0.2>, 0.6 pigment { rgb <1, 0.78, 0.34> } finish { Gold } }
sphere { <0.45, 0.7, -0.4>, 0.7 pigment { rgb 0.6 } finish { Chrome } }
sphere { <1.65, 0.5, 0.3>, 0.5 pigment { rgb <0.1, 0.3, 0.7> } finish { Plastic } }
sphere { 0, 0.45 rotate -90 * x translate <2.75, 0.45, -0.9> pigment { rgb 0.9 } finish { Brushed } }
sphere { <-1.55, 0.4, 1.5>, 0.4 pigment { rgbf <1, 1, 1, 1> } finish { Glass } interior { ior 1.5 } }
sphere { <0.75, 0.4, 1.45>, 0.4 pigment { rgb <0.55, 0.07, 0.2> } finish { Satin } }
