// Placeholder until the CLI lands.
#include <cstdio>
int main() { std::puts("janus: not built yet"); return 1; }
