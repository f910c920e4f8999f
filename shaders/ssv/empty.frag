// ssv: stencil-only passes (the volumes' and the wedges' z-fail counts) write no colour.
void main() {}
