// For tests that shade glTF inputs directly: std.gltf's material compiled once (4 wavelengths)
// and a flat shading point (normal +z, dpdu +x, dpdv +y).
#pragma once
#include <string>

#include <gtest/gtest.h>

#include "renderer/material/tex_binding.h"
#include "renderer/material/material_system.h"

namespace tex::render::test {

inline constexpr int kGltfEntryWavelengths = 4;

inline const CompiledGltf& gltfEntry() {
  static const CompiledGltf* compiled = [] {
    auto* c = new CompiledGltf;
    std::string error;
    EXPECT_TRUE(compileGltfMaterial(kGltfEntryWavelengths, false, false, *c, error)) << error;
    return c;
  }();
  return *compiled;
}

inline ShadingPoint flatPoint() {
  ShadingPoint p;
  p.p = Vec3(0.1f, 0.2f, 0.3f);
  p.ng = p.ns = Vec3(0, 0, 1);
  p.dpdu = Vec3(1, 0, 0);
  p.dpdv = Vec3(0, 1, 0);
  return p;
}

}  // namespace tex::render::test
