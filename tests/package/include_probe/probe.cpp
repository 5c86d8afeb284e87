// Includes the header PROBE_HEADER names (include_probe/CMakeLists.txt).
#include PROBE_HEADER

int ProbeCompiled() { return 1; }
