#include "renderer/material/material_system.h"

#include <atomic>

#include "renderer/material/closure_lobes.h"
#include "renderer/material/gltf_material.h"
#include "renderer/material/tex_binding.h"
#include "renderer/spectra/rgb_spectrum.h"

namespace tex::render {

namespace {

// Which binding (if any) a scene material uses: bindings match glTF material names first,
// then mesh names (a mesh match applies to primitives of that mesh, see bindingForPrimitive).
int bindingForMaterial(const SceneDescription& scene, int material) {
  if (material < 0 || size_t(material) >= scene.materials.size()) return -1;
  for (size_t i = 0; i < scene.texMaterials.size(); ++i)
    if (!scene.texMaterials[i].matchMaterial.empty() && scene.texMaterials[i].matchMaterial == scene.materials[size_t(material)].name)
      return int(i);
  return -1;
}

}  // namespace

struct MaterialSystem::Impl {
  const SceneDescription* scene = nullptr;
  MaterialOptions options;
  CompiledBindings compiled;
  std::vector<int> bindingOfMaterial;  // per scene material (+1 slot for the default, -1)
  std::vector<uint8_t> emissive;       // per material slot
  std::vector<float> averageEmission;  // per material slot
  mutable std::atomic<uint64_t> failures{0};

  int slot(int material) const {
    return material >= 0 && size_t(material) < scene->materials.size() ? material : int(scene->materials.size());
  }
};

MaterialSystem::~MaterialSystem() = default;

uint64_t MaterialSystem::failures() const { return impl_->failures.load(std::memory_order_relaxed); }

std::unique_ptr<MaterialSystem> MaterialSystem::create(const SceneDescription& scene, const MaterialOptions& options,
                                                       std::string& error) {
  std::unique_ptr<MaterialSystem> ms(new MaterialSystem());
  ms->impl_ = std::make_unique<Impl>();
  Impl& im = *ms->impl_;
  im.scene = &scene;
  im.options = options;
  if (!compileBindings(scene, options.wavelengths, options.quickCompile, options.useCache, im.compiled, error))
    return nullptr;
  ms->report_.texMaterials = int(im.compiled.bindings.size());
  ms->report_.compileMs = im.compiled.compileMs;
  ms->report_.cacheHit = im.compiled.cacheHit;
  const size_t slots = scene.materials.size() + 1;
  im.bindingOfMaterial.assign(slots, -1);
  for (size_t m = 0; m < scene.materials.size(); ++m) im.bindingOfMaterial[m] = bindingForMaterial(scene, int(m));
  // Mesh-name bindings apply to materials used only by that mesh's primitives: resolved per
  // primitive by the scene loader, which gives such primitives their own material slot.
  im.emissive.assign(slots, 0);
  im.averageEmission.assign(slots, 0.0f);
  // Probe each material once at a neutral point with a fixed wavelength group to learn whether
  // it emits (and roughly how much: light selection by power).
  Wavelengths probe = color::sampleWavelengthGroup(0.5f, options.wavelengths);
  ShadingPoint point;
  point.p = Vec3(0.0f);
  point.ng = point.ns = Vec3(0, 0, 1);
  point.uv = Vec2(0.5f);
  for (size_t s = 0; s < slots; ++s) {
    const int material = s < scene.materials.size() ? int(s) : -1;
    Bsdf bsdf(Frame::fromNormal(point.ns), point.ng);
    Spectrum e;
    bool sawEmission = false;
    if (im.bindingOfMaterial[s] >= 0) {
      ClosureEvaluation ev = evaluateBinding(im.compiled.bindings[size_t(im.bindingOfMaterial[s])], point, probe, bsdf, e);
      sawEmission = ev.sawEmission;
    } else if (material >= 0) {
      const GltfMaterial& gm = scene.materials[s];
      sawEmission = gm.emissiveFactor * gm.emissiveStrength != Vec3(0.0f);
      shadeGltfMaterial(scene, gm, point, probe, bsdf, e);
    }
    im.emissive[s] = sawEmission;
    im.averageEmission[s] = std::max(e.average(probe.count), 0.0f);
  }
  return ms;
}

bool MaterialSystem::shade(int material, const ShadingPoint& point, const Wavelengths& lambda, Bsdf& bsdf,
                           Spectrum& emission) const {
  const Impl& im = *impl_;
  const int s = im.slot(material);
  emission = Spectrum();
  if (im.bindingOfMaterial[size_t(s)] >= 0) {
    const ClosureEvaluation ev =
        evaluateBinding(im.compiled.bindings[size_t(im.bindingOfMaterial[size_t(s)])], point, lambda, bsdf, emission);
    if (!ev.ok) {
      im.failures.fetch_add(1, std::memory_order_relaxed);
      bsdf = Bsdf(bsdf.frame(), bsdf.geometricNormal());
      emission = Spectrum();
      return false;
    }
    return true;
  }
  if (material < 0 || size_t(material) >= im.scene->materials.size()) {
    Lobe grey;
    grey.kind = LobeKind::Lambertian;
    grey.weight = Spectrum(0.8f);
    bsdf.add(grey);
    return true;
  }
  shadeGltfMaterial(*im.scene, im.scene->materials[size_t(material)], point, lambda, bsdf, emission);
  return true;
}

Spectrum MaterialSystem::emission(int material, const ShadingPoint& point, const Wavelengths& lambda) const {
  const Impl& im = *impl_;
  const int s = im.slot(material);
  if (!im.emissive[size_t(s)]) return Spectrum();
  if (im.bindingOfMaterial[size_t(s)] < 0) return gltfEmission(*im.scene, im.scene->materials[size_t(material)], point, lambda);
  Bsdf bsdf(Frame::fromNormal(point.ns), point.ng);
  Spectrum e;
  shade(material, point, lambda, bsdf, e);
  return e;
}

bool MaterialSystem::isEmissive(int material) const { return impl_->emissive[size_t(impl_->slot(material))] != 0; }

bool MaterialSystem::emitsBothSides(int material) const {
  const Impl& im = *impl_;
  return material >= 0 && size_t(material) < im.scene->materials.size() && im.bindingOfMaterial[size_t(material)] < 0 &&
         im.scene->materials[size_t(material)].doubleSided;
}

float MaterialSystem::averageEmission(int material) const { return impl_->averageEmission[size_t(impl_->slot(material))]; }

}  // namespace tex::render
