#pragma once
// `mopad suite merge DIR... -o OUT`: joins suite folders of one manifest (the shards of a split
// run, or a run and its resumed parts) into one suite folder. Every case of the manifest must
// be finished in exactly one of them; the case folders (and made scenes) are copied into OUT
// and the result files written from the case results, so OUT equals a single-machine run of
// the manifest apart from the measured fields.

#include <string>
#include <vector>

namespace mopad::suite {

/// Returns the exit code (0 every case passed and every pooled check holds, 1 otherwise).
/// InputError when the folders' manifests differ, a case is missing or appears twice.
int MergeSuites(const std::vector<std::string>& dirs, const std::string& out, bool quiet);

}  // namespace mopad::suite
