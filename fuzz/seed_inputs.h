// seed_inputs: valid inputs for each fuzzed entry point (fuzz_inputs.h), made by sweepd's own
// writers from the small procedural mannequin, so the corpora start from what the parsers
// accept: a session of frames (Hello, Pose, LoadModel, EditKeyEllipse, PositionMapRequest), the
// mannequin as .glb, the smallest mannequin and a four-joint animation as FBX (assimp's
// exporter), a BVH written from its skeleton, its .sweepbind, each JSON input, a VMC frame (a
// liblo bundle), HTTP side-port requests, and the frames session as a WebSocket client sends it.
// Keys: "frames", "websocket", "gltf", "fbx", "bvh", "sweepbind", "json" (fuzz_json's first
// byte picks the kind), "vmc", "http". fuzz/make_seeds writes them to corpus folders;
// tests/fuzz/fuzz_inputs_test.cpp replays them.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace sweepd::fuzz {

using Input = std::vector<std::uint8_t>;

std::map<std::string, std::vector<Input>> seed_inputs();

}  // namespace sweepd::fuzz
