// The HUD overlay, straight (non-premultiplied) alpha; blended with
// (SRC_ALPHA, ONE_MINUS_SRC_ALPHA) over the window.
in vec2 v_uv;
out vec4 o_color;
uniform sampler2D u_overlay;
void main() { o_color = texture(u_overlay, v_uv); }
