#include "renderer/material/material_system.h"

#include <algorithm>
#include <atomic>
#include <cmath>

#include "renderer/material/closure_lobes.h"
#include "renderer/material/gltf_material.h"
#include "renderer/material/material_memo.h"
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
  CompiledGltf gltfMaterial;  // std.gltf.metallic_roughness, when some glTF material is unbound
  // Material slots: scene materials [0, M), the default grey M, then one slot per binding that
  // matches by mesh name (M + 1 + k). bindingOfMaterial maps a slot to its .tex binding or -1.
  std::vector<int> bindingOfMaterial;
  std::vector<int> slotOfPrimitive;  // per primitive: the slot its hits shade with
  std::vector<uint8_t> emissive;       // per material slot
  std::vector<uint8_t> passesStraightRays;  // per material slot: mayPassStraightRays
  // Per material slot: an unbound glTF material that reads no texture (gltfReadsHit), so
  // shade() may replay the path's earlier evaluation from the memo (material_memo.h).
  std::vector<uint8_t> gltfHitIndependent;
  Wavelengths probe;  // the fixed group materials are probed with
  std::vector<float> averageEmission;  // per material slot
  // Per binding: its closure tree when constant (closure_lobes.h), else an empty tree.
  std::vector<ConstantClosure> constantClosures;
  mutable std::atomic<uint64_t> failures{0};
  uint64_t memoId = newMaterialMemoId();  // this system's key in the per-thread memo

  int slot(int material) const {
    return material >= 0 && size_t(material) < bindingOfMaterial.size() ? material : int(scene->materials.size());
  }
  const GltfMaterial* gltf(int s) const { return size_t(s) < scene->materials.size() ? &scene->materials[size_t(s)] : nullptr; }
};

namespace {

// Slot s's binding at a point: its constant tree walked at these wavelengths when it has one
// (the compiled code would build the same tree), else the compiled code called.
bool evaluate(const MaterialSystem::Impl& im, int s, const ShadingPoint& point, const Wavelengths& lambda, Bsdf* bsdf,
              Spectrum& emission) {
  const size_t b = size_t(im.bindingOfMaterial[size_t(s)]);
  const ConstantClosure& tree = im.constantClosures[b];
  if (tree.root >= 0 && tree.wavelengthCount == lambda.count) return walkConstantClosure(tree, lambda, bsdf, emission).ok;
  return evaluateBinding(im.compiled.bindings[b], point, lambda, bsdf, emission).ok;
}

// A glTF material: its factors and textures read here, its scattering from std.gltf.
bool evaluateGltf(const MaterialSystem::Impl& im, const GltfMaterial& m, const ShadingPoint& point,
                  const Wavelengths& lambda, Bsdf& bsdf, Spectrum& emission) {
  if (m.unlit) {  // no lobes: an emitter of its base colour that absorbs what arrives
    emission = gltfEmission(*im.scene, m, point, lambda);
    return true;
  }
  applyGltfNormalMap(*im.scene, m, point, bsdf);
  GltfInputs in = gltfInputs(*im.scene, m, point);
  gltfAnisotropyInto(*im.scene, m, point, bsdf.frame(), in);
  const auto args = in.words();
  static_assert(args.size() == size_t(kGltfArgumentWords));
  const bool ok = evaluateEntry(im.gltfMaterial.entry, args.data(), kGltfArgumentWords, point, lambda, &bsdf, emission).ok;
  applyGltfClearcoatNormal(*im.scene, m, point, bsdf);
  return ok;
}

}  // namespace

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
  ms->report_.compileMs = im.compiled.compileMs;
  ms->report_.cacheHit = im.compiled.cacheHit;
  im.bindingOfMaterial.assign(scene.materials.size() + 1, -1);
  for (size_t m = 0; m < scene.materials.size(); ++m) im.bindingOfMaterial[m] = bindingForMaterial(scene, int(m));
  // Bindings by mesh name win over the primitive's glTF material (the more specific match).
  im.slotOfPrimitive.resize(scene.primitives.size());
  for (size_t p = 0; p < scene.primitives.size(); ++p) {
    const int material = scene.primitives[p].material;
    im.slotOfPrimitive[p] = material >= 0 && size_t(material) < scene.materials.size() ? material : int(scene.materials.size());
    for (size_t b = 0; b < scene.texMaterials.size(); ++b) {
      if (scene.texMaterials[b].matchMesh.empty() || scene.texMaterials[b].matchMesh != scene.primitives[p].meshName) continue;
      int slot = -1;
      for (size_t k = scene.materials.size() + 1; k < im.bindingOfMaterial.size(); ++k)
        if (im.bindingOfMaterial[k] == int(b)) slot = int(k);
      if (slot < 0) {
        slot = int(im.bindingOfMaterial.size());
        im.bindingOfMaterial.push_back(int(b));
      }
      im.slotOfPrimitive[p] = slot;
      break;
    }
  }
  const size_t slots = im.bindingOfMaterial.size();
  bool anyGltf = false;
  for (size_t m = 0; m < scene.materials.size(); ++m) anyGltf = anyGltf || im.bindingOfMaterial[m] < 0;
  if (anyGltf) {
    if (!compileGltfMaterial(options.wavelengths, options.quickCompile, options.useCache, im.gltfMaterial, error))
      return nullptr;
    ms->report_.compileMs += im.gltfMaterial.compileMs;
  }
  const Wavelengths probe = color::sampleWavelengthGroup(0.5f, options.wavelengths);
  im.probe = probe;
  // Bindings whose tree is the same at every hit and wavelength group: captured once here.
  im.constantClosures.resize(im.compiled.bindings.size());
  for (size_t b = 0; b < im.compiled.bindings.size(); ++b) {
    ShadingPoint point;
    point.ng = point.ns = Vec3(0, 0, 1);
    captureConstantClosure(im.compiled.bindings[b], point, probe, im.constantClosures[b]);
  }
  im.gltfHitIndependent.assign(slots, 0);
  for (size_t m = 0; m < scene.materials.size(); ++m)
    im.gltfHitIndependent[m] =
        im.bindingOfMaterial[m] < 0 && im.gltfMaterial.hitIndependent && !gltfReadsHit(scene, scene.materials[m]);
  // Vertex colours (COLOR_0) vary the base colour over a mesh whatever the material reads.
  for (size_t p = 0; p < scene.primitives.size(); ++p) {
    const int s = im.slotOfPrimitive[p];
    if (!scene.primitives[p].colors.empty() && s >= 0 && size_t(s) < slots) im.gltfHitIndependent[size_t(s)] = 0;
  }
  im.passesStraightRays.assign(slots, 0);
  for (size_t s = 0; s < slots; ++s) {
    const int binding = im.bindingOfMaterial[s];
    const GltfMaterial* m = im.gltf(int(s));
    if (binding >= 0) im.passesStraightRays[s] = im.compiled.bindings[size_t(binding)].mayBuildThinWall;
    else if (m) im.passesStraightRays[s] = m->thinWalled && m->transmissionFactor > 0.0f;
  }
  im.emissive.assign(slots, 0);
  im.averageEmission.assign(slots, 0.0f);
  // Probe each material on a 4 x 4 grid of uv (and positions) with a fixed wavelength group to
  // learn whether it emits and roughly how much (light selection by power; a patterned emitter
  // measured at one point could look black there).
  for (size_t s = 0; s < slots; ++s) {
    bool sawEmission = false;
    double sum = 0;
    int probes = 0;
    for (int gy = 0; gy < 4; ++gy)
      for (int gx = 0; gx < 4; ++gx, ++probes) {
        ShadingPoint point;
        point.uv = point.uv1 = Vec2((float(gx) + 0.5f) / 4.0f, (float(gy) + 0.5f) / 4.0f);
        point.p = Vec3(point.uv.x, point.uv.y, 0.0f);
        point.ng = point.ns = Vec3(0, 0, 1);
        Bsdf bsdf(Frame::fromNormal(point.ns), point.ng);
        Spectrum e;
        if (im.bindingOfMaterial[s] >= 0) {
          const ClosureEvaluation ev =
              evaluateBinding(im.compiled.bindings[size_t(im.bindingOfMaterial[s])], point, probe, &bsdf, e);
          sawEmission = sawEmission || ev.sawEmission;
        } else if (s < scene.materials.size()) {
          const GltfMaterial& gm = scene.materials[s];
          sawEmission = sawEmission || gm.unlit || gm.emissiveFactor * gm.emissiveStrength != Vec3(0.0f);
          e = gltfEmission(scene, gm, point, probe);
        }
        sum += std::max(e.average(probe.count), 0.0f);
      }
    im.emissive[s] = sawEmission;
    im.averageEmission[s] = float(sum / probes);
  }
  return ms;
}

bool MaterialSystem::shade(int material, const ShadingPoint& point, const Wavelengths& lambda, Bsdf& bsdf,
                           Spectrum& emission) const {
  const Impl& im = *impl_;
  const int s = im.slot(material);
  emission = Spectrum();
  const int binding = im.bindingOfMaterial[size_t(s)];
  if (binding < 0 && !im.gltf(s)) {
    Lobe grey;
    grey.kind = LobeKind::Lambertian;
    for (int i = 0; i < lambda.count; ++i) grey.weight.v[i] = 0.8f;  // lanes past the count stay zero
    bsdf.add(grey);
    return true;
  }
  // A material whose evaluation depends on the wavelengths alone (a Hit-independent .tex
  // binding, a glTF material without textures) replays this path's earlier evaluation
  // (material_memo.h); only onto an empty Bsdf, where the replay equals evaluating.
  const bool hitIndependent =
      binding >= 0 ? im.compiled.bindings[size_t(binding)].hitIndependent : im.gltfHitIndependent[size_t(s)] != 0;
  const bool memo = hitIndependent && bsdf.lobeCount() == 0 && !bsdf.hasCoat();
  if (memo) {
    if (const MaterialMemoEntry* e = materialMemoFind(im.memoId, s, true, lambda)) {
      bsdf.copyLobesFrom(e->bsdf);
      emission = e->emission;
      if (!e->ok) im.failures.fetch_add(1, std::memory_order_relaxed);
      return e->ok;
    }
  }
  const bool ok = binding >= 0 ? evaluate(im, s, point, lambda, &bsdf, emission)
                               : evaluateGltf(im, *im.gltf(s), point, lambda, bsdf, emission);
  if (!ok) {
    im.failures.fetch_add(1, std::memory_order_relaxed);
    bsdf = Bsdf(bsdf.frame(), bsdf.geometricNormal());
    emission = Spectrum();
  }
  if (memo) materialMemoStore(im.memoId, s, lambda, ok, emission, &bsdf);
  return ok;
}

Spectrum MaterialSystem::emission(int material, const ShadingPoint& point, const Wavelengths& lambda) const {
  const Impl& im = *impl_;
  const int s = im.slot(material);
  if (!im.emissive[size_t(s)]) return Spectrum();
  if (im.bindingOfMaterial[size_t(s)] < 0)
    return im.gltf(s) ? gltfEmission(*im.scene, *im.gltf(s), point, lambda) : Spectrum();
  const CompiledBinding& binding = im.compiled.bindings[size_t(im.bindingOfMaterial[size_t(s)])];
  if (binding.hitIndependent) {
    if (const MaterialMemoEntry* memo = materialMemoFind(im.memoId, s, false, lambda)) return memo->emission;
  }
  Spectrum e;
  if (!evaluate(im, s, point, lambda, nullptr, e)) e = Spectrum();
  if (binding.hitIndependent) materialMemoStore(im.memoId, s, lambda, true, e, nullptr);
  return e;
}

bool MaterialSystem::isEmissive(int material) const { return impl_->emissive[size_t(impl_->slot(material))] != 0; }

bool MaterialSystem::emitsBothSides(int material) const {
  const Impl& im = *impl_;
  const int s = im.slot(material);
  return im.gltf(s) && im.bindingOfMaterial[size_t(s)] < 0 && im.gltf(s)->doubleSided;
}

bool MaterialSystem::emissionUnderClearcoat(int material) const {
  const Impl& im = *impl_;
  const int s = im.slot(material);
  // (With KHR_materials_ior's 0, the compatibility mirror, std.gltf's clearcoat is a partial
  // coat over the mirror, not a clearcoat: not darkened; docs/gltf-extensions.md.)
  const GltfMaterial* m = im.gltf(s);
  return m && im.bindingOfMaterial[size_t(s)] < 0 && m->clearcoatFactor > 0.0f && m->ior != 0.0f && !m->unlit &&
         isEmissive(material);
}

bool MaterialSystem::interiorAbsorption(int material, const Wavelengths& lambda, Spectrum& sigmaA) const {
  const Impl& im = *impl_;
  const int s = im.slot(material);
  const GltfMaterial* m = im.gltf(s);
  if (!m || im.bindingOfMaterial[size_t(s)] >= 0 || !(m->thicknessFactor > 0.0f) || !(m->attenuationDistance > 0.0f) ||
      !std::isfinite(m->attenuationDistance))
    return false;
  const Spectrum c = rgbReflectanceSpectrum(glm::clamp(m->attenuationColor, Vec3(0.0f), Vec3(1.0f)), lambda);
  sigmaA = Spectrum();
  for (int i = 0; i < lambda.count; ++i)
    sigmaA.v[i] = c.v[i] > 0.0f ? -std::log(c.v[i]) / m->attenuationDistance : 1e30f;
  return true;
}

bool MaterialSystem::mayPassStraightRays(int material) const {
  const Impl& im = *impl_;
  return im.passesStraightRays[size_t(im.slot(material))] != 0;
}

bool MaterialSystem::anyMayPassStraightRays() const {
  const auto& p = impl_->passesStraightRays;
  return std::find(p.begin(), p.end(), 1) != p.end();
}

bool MaterialSystem::transmitsIntoAVolume(int material) const {
  const Impl& im = *impl_;
  const int s = im.slot(material);
  const GltfMaterial* m = im.gltf(s);
  return m && im.bindingOfMaterial[size_t(s)] < 0 && !m->thinWalled && m->transmissionFactor > 0.0f;
}

bool MaterialSystem::interiorIor(int material, const Wavelengths& lambda, Spectrum& eta) const {
  if (!transmitsIntoAVolume(material)) return false;
  const GltfMaterial& m = *impl_->gltf(impl_->slot(material));
  const float ior = m.ior >= 1.0f ? m.ior : 1.5f;
  eta = Spectrum(1.0f);
  for (int i = 0; i < lambda.count; ++i) eta.v[i] = gltfDispersiveIor(ior, m.dispersion, lambda.lambdaNm[i]);
  return true;
}

bool MaterialSystem::anyTransmitsIntoAVolume() const {
  for (size_t m = 0; m < impl_->scene->materials.size(); ++m)
    if (transmitsIntoAVolume(int(m))) return true;
  return false;
}

int MaterialSystem::materialOfPrimitive(int primitive) const {
  return primitive >= 0 && size_t(primitive) < impl_->slotOfPrimitive.size() ? impl_->slotOfPrimitive[size_t(primitive)]
                                                                              : int(impl_->scene->materials.size());
}

bool MaterialSystem::readsPixelFootprint(int material) const {
  const Impl& im = *impl_;
  const int s = im.slot(material);
  const int binding = im.bindingOfMaterial[size_t(s)];
  if (binding >= 0) return !im.compiled.bindings[size_t(binding)].hitIndependent;
  return false;  // glTF materials look their textures up bilinearly at the finest level
}

const Wavelengths& MaterialSystem::probeWavelengths() const { return impl_->probe; }

bool MaterialSystem::readsHit(int material) const {
  const Impl& im = *impl_;
  const int s = im.slot(material);
  const int binding = im.bindingOfMaterial[size_t(s)];
  if (binding >= 0) return !im.compiled.bindings[size_t(binding)].hitIndependent;
  return im.gltf(s) != nullptr && im.gltfHitIndependent[size_t(s)] == 0;
}

float MaterialSystem::averageEmission(int material) const { return impl_->averageEmission[size_t(impl_->slot(material))]; }

}  // namespace tex::render
