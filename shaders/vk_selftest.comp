#version 450
// Self-test of the vk/ layer (tests/gpu/vk_context_test.cpp): y[i] = x[i] * 2 + addend for the
// i < count covered by this dispatch. baseGroup is the first workgroup of a chunked dispatch
// (vk::dispatchChunked), so i counts across all chunks.
layout(local_size_x_id = 0) in;

layout(std430, set = 0, binding = 0) readonly buffer Input { float x[]; };
layout(std430, set = 0, binding = 1) writeonly buffer Output { float y[]; };

layout(push_constant) uniform Push {
  uint count;
  uint baseGroup;
  float addend;
  uint pad;
} pc;

void main() {
  uint i = (pc.baseGroup + gl_WorkGroupID.x) * gl_WorkGroupSize.x + gl_LocalInvocationID.x;
  if (i < pc.count) y[i] = x[i] * 2.0 + pc.addend;
}
