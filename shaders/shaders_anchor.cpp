// Anchors the shapespline_shaders library; the SPIR-V lives in generated headers.
