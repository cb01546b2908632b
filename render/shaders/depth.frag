// Depth only: the shadow map and the pen phantom (colour writes are masked).
void main() {}
