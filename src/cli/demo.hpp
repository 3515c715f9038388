// `rangekit demo`: the main job. Live by default (two emulators streamed and
// captured); `--walkthrough` decodes a sample session typed from the documents.
#pragma once

namespace rangekit::cli {

int run_walkthrough();

}  // namespace rangekit::cli
