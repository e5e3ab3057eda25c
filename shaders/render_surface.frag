#version 450
// Two-sided headlight shading: Lambert + Blinn-Phong from a light near the camera, a hemisphere
// ambient term, and the back side tinted so that inside and outside are told apart.
#extension GL_GOOGLE_include_directive : require
#define SHAPESPLINE_GLSL 1
#include "tess_layout.h"

layout(location = 0) in vec3 inWorld;
layout(location = 1) in vec3 inNormal;
layout(location = 2) in vec2 inUV;
layout(location = 0) out vec4 outColor;
layout(push_constant) uniform PushBlock { RenderPush pc; };

void main() {
  if (pc.params.x != 0.0) {
    outColor = vec4(pc.color.rgb, 1.0);
    return;
  }
  vec3 v = normalize(pc.eye.xyz - inWorld);
  float nl = length(inNormal);
  vec3 n = nl > 0.0 ? inNormal / nl : v;
  bool back = dot(n, v) < 0.0;
  if (back) n = -n;
  vec3 base = back ? vec3(0.85, 0.55, 0.35) : pc.color.rgb;
  vec3 l = normalize(v + vec3(0.3, 0.4, 0.2));
  float diff = max(dot(n, l), 0.0);
  float spec = pow(max(dot(n, normalize(l + v)), 0.0), 48.0);
  float hemi = 0.5 + 0.5 * n.z;
  vec3 c = base * (0.18 + 0.12 * hemi + 0.75 * diff) + vec3(0.25 * spec);
  outColor = vec4(clamp(c, 0.0, 1.0), 1.0);
}
