// The occluder mask into depth: pixels where something real stands in front
// of the tank get the near plane's depth (the triangle lies at z = -1), so
// nothing virtual is drawn over them.
uniform sampler2D u_mask;
void main() {
  // 1: an occluder; 0.5 (the pen's silhouette) only marks the video.
  if (texelFetch(u_mask, ivec2(gl_FragCoord.xy), 0).r < 0.75) discard;
}
