// Environment cube map faces (pass_envmap.h): the image coordinate divided
// per fragment, so the face's square maps onto its piece of the frame
// projectively (no crease along the quad's diagonal). Linear light.
in vec3 v_image;
out vec4 o_color;
uniform sampler2D u_source;  // the frame, top row at t = 0
void main() {
  o_color = vec4(
      DecodeVideo(textureLod(u_source, v_image.xy / v_image.z, 0.0).rgb), 1.0);
}
