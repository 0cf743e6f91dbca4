#include "renderer/integrators/render_scene.h"

#include <chrono>
#include <cmath>
#include <map>

#include "renderer/lights/light_factory.h"
#include "renderer/lights/triangle_light.h"

namespace tex::render {

// The emission of one material, as area lights see it.
struct RenderScene::Emission final : EmissionSource {
  const MaterialSystem* materials = nullptr;
  const SceneGeometry* geometry = nullptr;
  int material = -1;
  bool readsHit_ = false;  // the material's emission may depend on its Hit
  bool cutOut_ = false;    // some emitter of it has a glTF alphaMode: light samples see its coverage
  bool underClearcoat_ = false;  // MaterialSystem::emissionUnderClearcoat: darkened by direction
  Spectrum radiance(const EmitterPoint& point, const Wavelengths& lambda) const override {
    // Rays pass through cut-out parts (MASK) and through blended ones with probability
    // 1 - alpha (BLEND), so the emission they find is coverage x radiance on average; light
    // samples, which do not trace to the emitter, multiply by it (they lit the scene through
    // the cut-outs: a fully cut-out lamp still gave 0.037 of its light).
    if (cutOut_ && point.instance >= 0) {
      const float coverage = geometry->coverage(point.instance, point.triangle, point.b12.x, point.b12.y);
      return coverage > 0.0f ? uncovered(point, lambda) * coverage : Spectrum();
    }
    return uncovered(point, lambda);
  }
  Spectrum uncovered(const EmitterPoint& point, const Wavelengths& lambda) const {
    // A light sample's emission must be the one a ray hitting the same point sees (the path
    // tracer weighs the two by MIS): for materials that read their Hit, the whole shading
    // point (interpolated normal, both uv sets, tangent...) as a hit would give it.
    if ((readsHit_ || underClearcoat_) && point.instance >= 0) {
      SurfaceHit hit;
      geometry->surfaceAt(point.instance, point.triangle, point.b12.x, point.b12.y, hit);
      if (underClearcoat_ && point.w != Vec3(0.0f)) {
        // The whole material, as a hit shades it (path_tracer.cpp), for its clearcoat's factor.
        Bsdf bsdf(Frame::fromNormalTangent(hit.ns, hit.dpdu), hit.ng);
        Spectrum emitted;
        materials->shade(material, shadingPoint(hit), lambda, bsdf, emitted);
        return emitted.isBlack() || !bsdf.hasClearcoat() ? emitted : emitted * bsdf.clearcoatEmissionFactor(point.w);
      }
      return materials->emission(material, shadingPoint(hit), lambda);
    }
    // Otherwise the emission does not depend on the point (position and normal for form's sake).
    ShadingPoint sp;
    sp.p = point.p;
    sp.ng = sp.ns = point.n;
    return materials->emission(material, sp, lambda);
  }
  float averageRadiance() const override { return materials->averageEmission(material); }
  bool readsHit() const override { return readsHit_ || cutOut_ || underClearcoat_; }
  float radianceEstimate(const EmitterPoint& point) const override {
    if (!readsHit()) return averageRadiance();
    // The wavelength group MaterialSystem probes materials with, for a deterministic estimate.
    const Wavelengths& probe = materials->probeWavelengths();
    return radiance(point, probe).average(probe.count);
  }
};

RenderScene::~RenderScene() = default;

ShadingPoint RenderScene::shadingPoint(const SurfaceHit& hit) {
  ShadingPoint sp;
  sp.p = hit.p;
  sp.ng = hit.ng;
  sp.ns = hit.ns;
  sp.uv = hit.uv;
  sp.uv1 = hit.uv1;
  sp.color = hit.color;
  sp.dpdu = hit.dpdu;
  sp.dpdv = hit.dpdv;
  sp.tangent = hit.tangent;
  return sp;
}

CameraSettings chooseCamera(const SceneDescription& scene, const Bounds3& bounds, int index, float aspect) {
  CameraSettings s;
  s.aspect = aspect;
  if (index >= 0 && size_t(index) < scene.cameras.size()) {
    const CameraDesc& c = scene.cameras[size_t(index)];
    s.cameraToWorld = c.cameraToWorld;
    s.yFovRadians = c.yFovRadians;
    s.lensRadius = c.lensRadius;
    s.focusDistance = c.focusDistance;
    s.orthoHalfHeight = c.orthoHalfHeight;
    return s;
  }
  // Frame the bounding sphere: look at its centre from +z and a little above, far enough that
  // the sphere fits the narrower field of view.
  const Vec3 centre = boundsCenter(bounds);
  const float radius = std::max(boundsRadius(bounds), 1e-6f);
  s.yFovRadians = 0.6f;
  const float halfFov = 0.5f * std::min(s.yFovRadians, 2.0f * std::atan(std::tan(0.5f * s.yFovRadians) * aspect));
  const float distance = radius / std::sin(halfFov) * 1.05f;
  const Vec3 dir = glm::normalize(Vec3(0.0f, 0.35f, 1.0f));
  const Vec3 eye = centre + dir * distance;
  const Vec3 forward = glm::normalize(centre - eye);
  const Vec3 right = glm::normalize(glm::cross(forward, Vec3(0, 1, 0)));
  const Vec3 up = glm::cross(right, forward);
  Mat4 m(1.0f);
  m[0] = Vec4(right, 0.0f);
  m[1] = Vec4(up, 0.0f);
  m[2] = Vec4(-forward, 0.0f);
  m[3] = Vec4(eye, 1.0f);
  s.cameraToWorld = m;
  s.focusDistance = distance;
  return s;
}

std::unique_ptr<RenderScene> RenderScene::build(const SceneDescription& scene, const RenderSceneOptions& options,
                                                std::string& error) {
  const auto start = std::chrono::steady_clock::now();
  std::unique_ptr<RenderScene> rs(new RenderScene());
  rs->desc_ = &scene;
  rs->geometry_ = SceneGeometry::build(scene, error);
  if (!rs->geometry_) return nullptr;
  MaterialOptions mo;
  mo.wavelengths = options.wavelengths;
  mo.quickCompile = options.quickCompile;
  mo.useCache = options.useCache;
  rs->materials_ = MaterialSystem::create(scene, mo, error);
  if (!rs->materials_) return nullptr;

  // Embree asserts (and aborts) on ray origins beyond about 1.8e18; keep every origin, a
  // surface's or the camera's, well inside that.
  constexpr float kMaxCoordinate = 1e15f;
  const Bounds3 bounds = rs->geometry_->bounds();
  if (!bounds.empty() && !(maxAbsComponent(bounds.lower) < kMaxCoordinate && maxAbsComponent(bounds.upper) < kMaxCoordinate)) {
    error = "the geometry reaches beyond 1e15 units from the origin, which ray tracing does not support";
    return nullptr;
  }
  const float aspect = float(options.width) / float(std::max(options.height, 1));
  const CameraSettings cs = chooseCamera(scene, bounds, scene.settings.camera, aspect);
  const float cameraReach = maxAbsComponent(Vec3(cs.cameraToWorld[3])) + cs.lensRadius +
                            cs.orthoHalfHeight * (1.0f + std::max(aspect, 1.0f));
  if (!(cameraReach < kMaxCoordinate) || !std::isfinite(glm::determinant(glm::mat3(cs.cameraToWorld)))) {
    const bool sceneCamera = scene.settings.camera >= 0 && size_t(scene.settings.camera) < scene.cameras.size();
    error = (sceneCamera ? "camera " + std::to_string(scene.settings.camera) : std::string("the camera framing the scene")) +
            ": its position, lens radius or orthographic extent reaches beyond 1e15 units from the origin, which ray tracing does not support";
    return nullptr;
  }
  rs->camera_ = std::make_unique<Camera>(cs);

  for (const LightDesc& ld : scene.lights) {
    std::unique_ptr<Light> light = makeLight(ld, error);
    if (!light) return nullptr;
    rs->lights_.push_back(std::move(light));
  }
  // One triangle light per emissive triangle of every instance.
  std::map<int, RenderScene::Emission*> emissionOfMaterial;
  const auto emissionFor = [&](int slot) -> const EmissionSource* {
    if (!emissionOfMaterial[slot]) {
      auto e = std::make_unique<RenderScene::Emission>();
      e->materials = rs->materials_.get();
      e->geometry = rs->geometry_.get();
      e->material = slot;
      e->readsHit_ = rs->materials_->readsHit(slot);
      e->underClearcoat_ = rs->materials_->emissionUnderClearcoat(slot);
      emissionOfMaterial[slot] = e.get();
      rs->emissionSources_.push_back(std::move(e));
    }
    return emissionOfMaterial[slot];
  };
  const int instanceCount = int(scene.instances.size());
  // Whether each emissive material has a cut-out emitter, before any light asks readsHit().
  for (int i = 0; i < instanceCount; ++i) {
    if (!rs->geometry_->hasInstance(i) || !rs->geometry_->cutOut(i)) continue;
    const int material = rs->materials_->materialOfPrimitive(scene.instances[size_t(i)].primitive);
    if (!rs->materials_->isEmissive(material)) continue;
    emissionFor(material);
    emissionOfMaterial[material]->cutOut_ = true;
  }
  rs->areaLightBase_.assign(size_t(instanceCount), -1);
  for (int i = 0; i < instanceCount; ++i) {
    if (!rs->geometry_->hasInstance(i)) continue;
    const int primitive = scene.instances[size_t(i)].primitive;
    const MeshPrimitive* prim = &scene.primitives[size_t(primitive)];
    const int material = rs->materials_->materialOfPrimitive(primitive);
    if (!rs->materials_->isEmissive(material) || prim->indices.empty()) continue;
    rs->areaLightBase_[size_t(i)] = int64_t(rs->lights_.size());
    const EmissionSource* source = emissionFor(material);
    const uint32_t triangles = uint32_t(prim->indices.size() / 3);
    for (uint32_t t = 0; t < triangles; ++t) {
      TriangleLightDesc d;
      Vec3 p[3];
      Vec2 uv[3];
      Vec3 ng;
      rs->geometry_->triangleWorld(i, t, p, uv, ng);
      d.p0 = p[0];
      d.p1 = p[1];
      d.p2 = p[2];
      d.normal = ng;
      d.primitive = scene.instances[size_t(i)].primitive;
      d.instance = i;
      d.triangle = t;
      d.twoSided = rs->materials_->emitsBothSides(material);
      rs->lights_.push_back(makeTriangleLight(d, source));
      ++rs->triangleLights_;
    }
  }
  if (rs->lights_.empty()) {
    // A file without lights (most glTF models) still gives a picture: a uniform white sky of
    // radiance 1, as viewers do. Reported as a note so nobody mistakes it for the scene's light.
    LightDesc sky;
    sky.kind = LightDesc::Kind::ConstantEnvironment;
    sky.name = "default sky";
    sky.emission.kind = SpectrumDesc::Kind::Rgb;
    sky.emission.rgb = Vec3(1.0f);
    sky.intensity = 1.0f;
    std::unique_ptr<Light> light = makeLight(sky, error);
    if (!light) return nullptr;
    rs->lights_.push_back(std::move(light));
    rs->addedDefaultLight_ = true;
  }
  const Bounds3& b = rs->geometry_->bounds();
  SceneSphere sphere{boundsCenter(b), std::max(boundsRadius(b), 1e-6f)};
  for (size_t i = 0; i < rs->lights_.size(); ++i) {
    rs->lights_[i]->preprocess(sphere);
    rs->lightPointers_.push_back(rs->lights_[i].get());
    if (rs->lights_[i]->kind() == LightKind::ConstantEnvironment || rs->lights_[i]->kind() == LightKind::ImageEnvironment)
      rs->environmentLights_.push_back(int(i));
  }
  rs->lightSampler_ = std::make_unique<LightSampler>(std::span<const Light* const>(rs->lightPointers_));
  rs->buildSeconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return rs;
}

int RenderScene::areaLightAt(const SurfaceHit& hit) const {
  if (hit.instance < 0 || size_t(hit.instance) >= areaLightBase_.size()) return -1;
  const int64_t base = areaLightBase_[size_t(hit.instance)];
  return base < 0 ? -1 : int(base + int64_t(hit.triangle));
}

}  // namespace tex::render
