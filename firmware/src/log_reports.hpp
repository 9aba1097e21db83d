#pragma once

#include <string>

#include "cleanslam/firmware/loop.hpp"
#include "cleanslam/readers/log_source.hpp"

// What the program tells of a recorded log it runs or replays, on stderr.
namespace cleanslam::firmware {

// What a log source skipped while replaying, and why; counted by the loop when given.
void report_log_source(const readers::LogSource& source, const std::string& name, Loop* loop);
// The first file's configuration record is what a replay runs with: it must be the recorded one.
// False (after the message) when its hash does not match and `fatal`.
bool config_hash_checked(const readers::LogReader& reader, bool fatal);
// A replay must begin where the run began: in the file of index 0, and go on in order. False after
// a message that says how to join the rotated files, or why it cannot be done.
bool replayable_alone(const readers::LogReader& log, const std::string& path);
// The damaged records the reader skipped, by kind; counted by the loop when given.
void report_log_defects(const readers::LogReader& reader, Loop* loop);

}  // namespace cleanslam::firmware
