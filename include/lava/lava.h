// Lava: a Vulkan compute-shader particle engine. This header is what a host needs: the
// device, scenes, the simulations, the renderers, states and errors.
//
//   lava::Device device(handles);                  // the host's VkInstance, device, queue
//   lava::GpuSimulation sim(device, scene);        // scene: lava::Scene or loadScene(path)
//   lava::LineRenderer lines(device, {colorFormat, depthFormat});
//   per frame: sim.update(frame, steps); sim.recordSimulate(cmd, frame);
//              lines.recordPrepare(cmd, frame, sim, view);
//              vkCmdBeginRendering(...); lines.recordDraw(cmd, frame, sim, view); ...
//
// Tools a host may ignore have headers of their own: <lava/validation.h> (comparing
// backends), <lava/checkpoint.h> (checkpoint files), <lava/scene_keys.h> (scene keys as
// text), <lava/bench.h> (compute ceilings).
#pragma once
#include "camera.h"
#include "device.h"
#include "error.h"
#include "lava/version.h"
#include "math.h"
#include "renderer.h"
#include "scene.h"
#include "simulation.h"
#include "state.h"
