#version 450
// Overlay lines and markers (curves, control nets, data points): position + screen-space offset in
// pixels (markers are small quads expanded on the host) + colour; pulled slightly towards the camera.
#extension GL_GOOGLE_include_directive : require
#define SHAPESPLINE_GLSL 1
#include "tess_layout.h"

layout(location = 0) in vec3 inPosition;
layout(location = 1) in vec2 inOffset;
layout(location = 2) in vec4 inColor;
layout(location = 0) out vec4 outColor;
layout(push_constant) uniform PushBlock { RenderPush pc; };

void main() {
  vec4 clip = pc.viewProj * vec4(inPosition, 1.0);
  clip.xy += inOffset * 2.0 / pc.params.zw * clip.w;
  clip.z -= pc.params.y * clip.w;
  gl_Position = clip;
  outColor = inColor;
}
