#version 450
// Shaded surface / wireframe of a tessellated mesh (tess_layout.h vertex), host/render/renderer.cpp.
#extension GL_GOOGLE_include_directive : require
#define SHAPESPLINE_GLSL 1
#include "tess_layout.h"

layout(location = 0) in vec3 inPosition;
layout(location = 1) in vec3 inNormal;
layout(location = 2) in vec2 inUV;
layout(location = 0) out vec3 outWorld;
layout(location = 1) out vec3 outNormal;
layout(location = 2) out vec2 outUV;
layout(push_constant) uniform PushBlock { RenderPush pc; };

void main() {
  outWorld = inPosition;
  outNormal = inNormal;
  outUV = inUV;
  vec4 clip = pc.viewProj * vec4(inPosition, 1.0);
  // Lines drawn over the surface are pulled towards the camera so that they win the depth test.
  clip.z -= pc.params.y * clip.w;
  gl_Position = clip;
}
