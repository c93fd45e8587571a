#version 460
// Tessellator capture: one patch whose control points carry nothing.
void main() {
}
