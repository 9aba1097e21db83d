namespace cleanslam::sim_hal {

const char* version() {
  return "0.1.0";
}

}  // namespace cleanslam::sim_hal
