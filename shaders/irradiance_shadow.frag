#version 450
// Shadow pass: depth only (the framebuffer has no colour attachment).
void main() {}
