#pragma once
// The bare Embree baseline of `mopad bench raycast`: the same pulse grid and pose as a
// TlsScanner scan, traced in the same 16-wide packets over the same column blocks in parallel
// (TBB), storing only hit distances. It is the practical ray-casting limit of the machine that
// the full sensor model is compared against. Timing is the caller's business (tools/).

#include <cstdint>
#include <vector>

#include "sim/tls_scanner.h"

namespace mopad::sim {

/// Traces one ray per pulse of `scanner`'s grid from the nominal scanner pose of `request`
/// (X_WB * X_BS, no tilt, no jitter). `distances` (resized to rows * columns, column-major:
/// column * rows + row) receives t or +inf. Returns the number of hits.
std::uint64_t BareRaycast(const EmbreeWorld& world, const TlsScanner& scanner,
                          const ScanRequest& request, std::vector<float>& distances);

}  // namespace mopad::sim
