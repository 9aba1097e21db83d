"""cleanslam's PC-side evaluation code shared by the scripts in tools/eval."""
