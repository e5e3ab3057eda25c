#version 450
// fp64 twin of vk_selftest.comp, a separate module because any double in a module needs the
// Float64 capability, which a device without shaderFloat64 refuses even in dead code.
layout(local_size_x_id = 0) in;

layout(std430, set = 0, binding = 0) readonly buffer Input { double x[]; };
layout(std430, set = 0, binding = 1) writeonly buffer Output { double y[]; };

layout(push_constant) uniform Push {
  uint count;
  uint baseGroup;
  double addend;
} pc;

void main() {
  uint i = (pc.baseGroup + gl_WorkGroupID.x) * gl_WorkGroupSize.x + gl_LocalInvocationID.x;
  if (i < pc.count) y[i] = x[i] * 2.0lf + pc.addend;
}
