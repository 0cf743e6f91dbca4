// Image texture lookups for glTF materials: wrap modes, KHR_texture_transform, bilinear
// filtering, and sRGB decoding of colour textures. glTF's uv (0,0) is the image's top-left
// corner (no v flip).
#pragma once
#include "renderer/core/geometry.h"
#include "renderer/scene/scene_description.h"

namespace tex::render {

// Whether a lookup of `ref` reads an image (else it returns its fallback).
bool textureHasImage(const SceneDescription& scene, const TextureRef& ref);

// RGBA at uv (channels missing from the image read as: grey for 1-2 channels, alpha 1).
// Colour textures pass srgb = true (the alpha channel stays linear). Returns `fallback` when
// the reference has no image.
Vec4 lookupTexture(const SceneDescription& scene, const TextureRef& ref, Vec2 uv0, Vec2 uv1, bool srgb,
                   const Vec4& fallback = Vec4(1.0f));

}  // namespace tex::render
