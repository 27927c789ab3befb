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
using LoadMemoryFn = bool (*)(const std::string&, const unsigned char*, std::size_t,
                              const TexelImageOptions&, const std::string&, TexelImage&,
                              std::string&);

// The module's entry points, looked up once.
struct Module {
    LoadFn load = nullptr;
    LoadMemoryFn load_memory = nullptr;
    std::string tried;
};

constexpr const char* kModuleName = "libfacet_oiio.so";

// The module, searched in order: $FACET_OIIO_MODULE; beside the binary that holds this code (the
// Python extension's folder, also inside the Blender addon); the build tree's copy.
void* load_module(std::string& tried) {
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
        if (dlsym(h, "facet_oiio_load_texel_image")) return h;
        tried += "\n  " + c + ": no entry point facet_oiio_load_texel_image";
    }
    return nullptr;
}

const Module& module() {
    static const Module m = [] {
        Module r;
        if (void* h = load_module(r.tried)) {
            r.load = reinterpret_cast<LoadFn>(dlsym(h, "facet_oiio_load_texel_image"));
            r.load_memory =
                reinterpret_cast<LoadMemoryFn>(dlsym(h, "facet_oiio_load_texel_image_memory"));
        }
        return r;
    }();
    return m;
}

[[noreturn]] void unavailable(const std::string& where, const std::string& path) {
    throw TexelImageError(where + ": " + path + ": image support (OpenImageIO, " + kModuleName +
                          ") is not available; tried:" + module().tried);
}

}  // namespace

TexelImage load_texel_image(const std::string& path, const TexelImageOptions& options,
                            const std::string& where) {
    const LoadFn fn = module().load;
    if (!fn) unavailable(where, path);
    TexelImage out;
    std::string error;
    if (!fn(path, options, where, out, error)) throw TexelImageError(error);
    return out;
}

TexelImage load_texel_image_memory(const std::string& name, std::span<const unsigned char> bytes,
                                   const TexelImageOptions& options, const std::string& where) {
    const LoadMemoryFn fn = module().load_memory;
    if (!fn) unavailable(where, name);
    TexelImage out;
    std::string error;
    if (!fn(name, bytes.data(), bytes.size(), options, where, out, error))
        throw TexelImageError(error);
    return out;
}

std::shared_ptr<const TexelImage> TexelImageCache::get_memory(const std::string& name,
                                                              std::span<const unsigned char> bytes,
                                                              const TexelImageOptions& options,
                                                              const std::string& where) {
    const auto key = std::make_tuple(name, int(options.color_space), options.reject_negative);
    std::lock_guard lock(m_mutex);
    auto it = m_images.find(key);
    if (it != m_images.end()) return it->second;
    auto image =
        std::make_shared<const TexelImage>(load_texel_image_memory(name, bytes, options, where));
    m_images.emplace(key, image);
    return image;
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
