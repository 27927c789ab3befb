// Image files as rendering data (texel_image.h): the cache, and load_texel_image, which calls
// the OpenImageIO module (texel_image_oiio.cpp, libfacet_oiio.so) loaded on first use, so that
// scenes without images never load OpenImageIO and its ~250 libraries.
#include "facet/render/texel_image.h"

#include <dlfcn.h>

#include <cstdlib>
#include <filesystem>
#include <mutex>

namespace facet::render {

namespace {

using LoadFn = bool (*)(const std::string&, const TexelImageOptions&, const std::string&,
                        TexelImage&, std::string&);

constexpr const char* kModuleName = "libfacet_oiio.so";

// The module, searched in order: $FACET_OIIO_MODULE; beside the binary that holds this code (the
// Python extension's folder, also inside the Blender addon); the build tree's copy.
LoadFn load_module(std::string& tried) {
    std::vector<std::string> candidates;
    if (const char* env = std::getenv("FACET_OIIO_MODULE"); env && *env) candidates.push_back(env);
    Dl_info info{};
    if (dladdr(reinterpret_cast<void*>(&load_module), &info) && info.dli_fname) {
        std::error_code ec;
        const auto dir = std::filesystem::weakly_canonical(info.dli_fname, ec).parent_path();
        if (!ec) candidates.push_back((dir / kModuleName).string());
    }
#ifdef FACET_OIIO_MODULE
    candidates.push_back(FACET_OIIO_MODULE);
#endif
    for (const std::string& c : candidates) {
        if (!std::filesystem::exists(c)) {
            tried += "\n  " + c + ": not found";
            continue;
        }
        void* h = dlopen(c.c_str(), RTLD_NOW | RTLD_LOCAL);
        if (!h) {
            tried += "\n  " + c + ": " + dlerror();
            continue;
        }
        if (void* f = dlsym(h, "facet_oiio_load_texel_image")) return reinterpret_cast<LoadFn>(f);
        tried += "\n  " + c + ": no entry point facet_oiio_load_texel_image";
    }
    return nullptr;
}

}  // namespace

TexelImage load_texel_image(const std::string& path, const TexelImageOptions& options,
                            const std::string& where) {
    static std::once_flag once;
    static LoadFn fn = nullptr;
    static std::string tried;
    std::call_once(once, [] { fn = load_module(tried); });
    if (!fn)
        throw TexelImageError(where + ": " + path + ": image support (OpenImageIO, " + kModuleName +
                              ") is not available; tried:" + tried);
    TexelImage out;
    std::string error;
    if (!fn(path, options, where, out, error)) throw TexelImageError(error);
    return out;
}

std::shared_ptr<const TexelImage> TexelImageCache::get(const std::string& path,
                                                       const TexelImageOptions& options,
                                                       const std::string& where) {
    std::error_code ec;
    std::string key_path = std::filesystem::weakly_canonical(path, ec).string();
    if (ec) key_path = path;
    const auto key = std::make_tuple(key_path, int(options.color_space), options.reject_negative);
    std::lock_guard lock(m_mutex);
    auto it = m_images.find(key);
    if (it != m_images.end()) return it->second;
    auto image = std::make_shared<const TexelImage>(load_texel_image(path, options, where));
    m_images.emplace(key, image);
    return image;
}

std::size_t TexelImageCache::size() const {
    std::lock_guard lock(m_mutex);
    return m_images.size();
}

std::size_t TexelImageCache::bytes() const {
    std::lock_guard lock(m_mutex);
    std::size_t b = 0;
    for (const auto& [k, img] : m_images) b += img->texels.size() * sizeof(float);
    return b;
}

}  // namespace facet::render
