// Everything an integrator reads, built from a SceneDescription: Embree geometry, compiled
// materials, lights (punctual and environment lights from the file, one triangle light per
// emissive triangle), the light sampler and the camera. Read-only while rendering.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "renderer/camera/camera.h"
#include "renderer/geometry/scene_geometry.h"
#include "renderer/lights/light_sampler.h"
#include "renderer/material/material_system.h"
#include "renderer/scene/scene_description.h"

namespace tex::render {

struct RenderSceneOptions {
  int width = 512, height = 512;  // for the camera's aspect ratio
  int wavelengths = 4;
  bool quickCompile = false;
  bool useCache = true;
};

class RenderScene {
 public:
  // The render scene keeps pointers into `scene` (meshes, materials, images): the description
  // must outlive it.
  static std::unique_ptr<RenderScene> build(const SceneDescription& scene, const RenderSceneOptions& options,
                                            std::string& error);
  ~RenderScene();

  const SceneDescription& description() const { return *desc_; }
  const SceneGeometry& geometry() const { return *geometry_; }
  const MaterialSystem& materials() const { return *materials_; }
  const Camera& camera() const { return *camera_; }
  const std::vector<const Light*>& lights() const { return lightPointers_; }
  const LightSampler& lightSampler() const { return *lightSampler_; }
  // Lights that rays escaping the scene see (environments; directional lights are Dirac).
  const std::vector<int>& environmentLights() const { return environmentLights_; }
  // The triangle light at a hit (-1 if the hit triangle does not emit).
  int areaLightAt(const SurfaceHit& hit) const;
  int triangleLightCount() const { return triangleLights_; }
  // Shading point of a hit, with the emitting-side convention of area lights.
  static ShadingPoint shadingPoint(const SurfaceHit& hit);
  double buildSeconds() const { return buildSeconds_; }
  // True when the scene had no light at all and a uniform white sky (radiance 1) was added.
  bool addedDefaultLight() const { return addedDefaultLight_; }

  struct Emission;

 private:
  RenderScene() = default;
  const SceneDescription* desc_ = nullptr;
  std::unique_ptr<SceneGeometry> geometry_;
  std::unique_ptr<MaterialSystem> materials_;
  std::unique_ptr<Camera> camera_;
  std::vector<std::unique_ptr<EmissionSource>> emissionSources_;
  std::vector<std::unique_ptr<Light>> lights_;
  std::vector<const Light*> lightPointers_;
  std::unique_ptr<LightSampler> lightSampler_;
  std::vector<int> environmentLights_;
  std::vector<int64_t> areaLightBase_;  // per geometry instance: light index of its triangle 0, or -1
  int triangleLights_ = 0;
  double buildSeconds_ = 0;
  bool addedDefaultLight_ = false;
};

// A camera for a scene: the file's camera `index`, else one framing the bounds from the +z side
// (slightly above), with the given aspect ratio.
CameraSettings chooseCamera(const SceneDescription& scene, const Bounds3& bounds, int index, float aspect);

}  // namespace tex::render
