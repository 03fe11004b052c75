// SPDX-License-Identifier: MIT
// SIGINT / SIGTERM ask a run to stop: the handler only sets a flag, the run loop checks it
// after every step and writes a checkpoint. A second signal takes the default action (the
// process ends at once), for a run that does not react.
#pragma once

#include <atomic>

namespace fesph {

/// Install the handlers; returns the flag they set.
const std::atomic<bool>* installStopSignals();

/// The signal that set the flag (0: none yet).
int stopSignal();

}  // namespace fesph
