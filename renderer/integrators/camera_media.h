// The volumes a point lies inside, for paths that start there (the camera): a path keeps the
// volumes it enters (medium_stack.h), but a camera under water or inside glass starts inside
// one without entering it.
#pragma once

#include "renderer/core/geometry.h"
#include "renderer/geometry/scene_geometry.h"
#include "renderer/integrators/medium_stack.h"
#include "renderer/material/material_system.h"

namespace tex::render {

// The KHR_materials_volume interiors (MaterialSystem::transmitsIntoAVolume) around `p`, the
// outermost entered first: a volume encloses p when rays from p meet its material's surfaces
// first from behind (leaving), by the majority of the three rays that meet them (so that one
// grazing an edge does not decide; and an open surface such as a sea modelled as a plane
// encloses what is below it, not what is above), and of nested volumes the one whose surface
// the rays meet first is the innermost. Volumes of .tex materials (refracting solids without
// a declared interior) are not found. A ray along `forward` (the camera's view; 0: none), when
// it meets a volume's surfaces, decides for that volume alone, so that a camera placed exactly
// on a surface starts on the side its own rays cross it from.
MediumStack mediaAroundPoint(const SceneGeometry& geometry, const MaterialSystem& materials, const Vec3& p,
                             const Vec3& forward = Vec3(0.0f));

}  // namespace tex::render
