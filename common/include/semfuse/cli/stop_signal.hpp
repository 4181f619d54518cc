#pragma once
// Ctrl-C / SIGTERM as a flag that long-running loops poll, so that a program stops between two
// frames and still flushes what it sent (a camera waits for acknowledgements, a segmenter
// publishes the frame in hand).
namespace semfuse::cli {

void installStopHandler();
bool stopRequested();

}  // namespace semfuse::cli
