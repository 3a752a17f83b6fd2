// A flow emitter's lattice fill (docs/model.md, "The flow", "Lattice fill"): its burst placed
// at rest on the cubic lattice of the emitter's spacing (mass / density)^(1/3), centred in its
// shape, in a fixed order. Which site a birth takes is integer arithmetic, written once here
// and once in flow.comp (latticeSite); its position is one float product and one sum.
#pragma once
#include <cstddef>
#include <cstdint>

#include "lava/scene.h"
#include "shared.h"

namespace lava::detail {

// The lattice as flow.comp reads it (gpu::FlowEmitterParams::lattice and ::spacing), and the
// number of its sites.
struct Lattice {
  // x: gpu::kFillRandom (no lattice), kFillBox or kFillBall. Box: y, z, w the sites along x,
  // y and z. Ball (a sphere, or a disc when it has one layer): y the largest i^2 + j^2 + k^2
  // of a site (integer offsets from the centre), z its integer square root, w the layers
  // below and above the centre (0 for a disc).
  gpu::uvec4 shape{};
  // x the spacing (m); box: y, z, w the offset of the centre in sites, (n - 1) / 2 per axis.
  gpu::vec4 spacing{};
  uint64_t sites = 0;
};

// Emitter `emitter`'s lattice (shape.x == kFillRandom unless its fill is Lattice). The scene's
// spacing must be valid (checkScene's flow checks); a lattice too large to index is
// InvalidArgument naming emitter[k].fill.
Lattice flowLattice(const Scene& scene, size_t emitter);

// Site `index` (below lattice.sites) as integer offsets along x, y, z: for a box, the sites
// along x, then z, then y (layers from the bottom up); for a ball, by layer from the bottom,
// then by row along z, then along x.
void latticeSite(const Lattice& lattice, uint32_t index, int32_t offset[3]);

// Its position: position + spacing (offset - centre) per axis, in float32.
Vec3 latticePosition(const Lattice& lattice, const Vec3& position, uint32_t index);

}  // namespace lava::detail
