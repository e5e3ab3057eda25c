#pragma once
// What the glTF writers share (io/gltf_writer.cpp for grids, io/triangle_mesh.cpp for part
// meshes): building a tinygltf::Model's buffer, views and accessors, JSON as tinygltf values, and
// serializing the model as .glb or as .gltf + .bin through AtomicFiles. Internal to io.
#include <shapespline/io/atomic_file.h>

#include <nlohmann/json_fwd.hpp>
#include <tiny_gltf.h>

#include <cstddef>
#include <vector>

namespace shapespline::io {

// JSON as a tinygltf::Value; integers beyond int32 become reals (tinygltf's integers are int).
tinygltf::Value gltfValue(const nlohmann::json& j);

// Appends `bytes` to buffer 0 at a 4-byte aligned offset as a new buffer view; returns its index.
int addGltfView(tinygltf::Model& m, const void* data, size_t bytes, int target);
// A new accessor of `view` from offset 0; returns its index.
int addGltfAccessor(tinygltf::Model& m, int view, int componentType, int type, size_t count,
                    std::vector<double> min = {}, std::vector<double> max = {});
// Per-component min/max of `values` (k per vertex), as the stored floats are (the validator
// compares POSITION's min/max with them exactly).
void gltfBounds(const std::vector<float>& values, int k, std::vector<double>& min, std::vector<double>& max);

// Serializes `model` (one buffer, buffer 0) by tinygltf: `bin` null, a .glb into `out`; else the
// .gltf JSON into `out`, its buffer pointing at `bin`'s file name (percent-encoded), and the bytes
// into `bin` (the two committed by one io::OutputSet). tinygltf's stream writer would embed a
// .gltf's buffer as base64, so the JSON is written with an empty buffer whose "uri" and
// "byteLength" are set afterwards. Throws OutputWriteError when tinygltf or a write fails.
void writeGltfModel(tinygltf::Model& model, AtomicFile& out, AtomicFile* bin);

}  // namespace shapespline::io
