// Positions given in normalised device coordinates (the coarse grid's
// stencil polygon, pass_water.h).
layout(location = 0) in vec2 a_ndc;
void main() { gl_Position = vec4(a_ndc, 0.0, 1.0); }
