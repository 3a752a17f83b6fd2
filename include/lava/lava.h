// Lava: a Vulkan compute-shader particle engine. Include this one header.
//
//   lava::Device device(handles);                  // the host's VkInstance, device, queue
//   lava::GpuSimulation sim(device, scene);        // scene: lava::Scene or loadScene(path)
//   lava::LineRenderer lines(device, {colorFormat, depthFormat});
//   per frame: sim.update(frame, steps); sim.recordSimulate(cmd, frame);
//              lines.recordPrepare(cmd, frame, sim, view);
//              vkCmdBeginRendering(...); lines.recordDraw(cmd, frame, sim, view); ...
#pragma once
#include "bench.h"
#include "camera.h"
#include "checkpoint.h"
#include "device.h"
#include "error.h"
#include "lava/version.h"
#include "math.h"
#include "renderer.h"
#include "scene.h"
#include "simulation.h"
#include "state.h"
#include "validation.h"
