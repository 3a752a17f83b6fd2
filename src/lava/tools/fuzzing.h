// What the fuzz targets (fuzz/) change in the library, and nothing else does.
#pragma once

namespace lava {

// Whether the checkpoint reader compares the CRCs and the checksum: always, but in the fuzz
// targets, which turn it off so that mutated inputs reach the parsing behind the sums, as
// fuzzed decoders of other formats do (docs/fuzzing.md).
void compareCheckpointSums(bool compare);

}  // namespace lava
