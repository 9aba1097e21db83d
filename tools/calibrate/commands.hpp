#pragma once

// cleanslam-calibrate's subcommands, one file each; each returns the program's exit status.
namespace cleanslam::calibrate {

inline constexpr const char* kProgram = "cleanslam-calibrate";

int wheels_command(int argc, char** argv);  // argv[0] is "wheels"
int gyro_command(int argc, char** argv);
int camera_command(int argc, char** argv);
int mount_command(int argc, char** argv);

}  // namespace cleanslam::calibrate
