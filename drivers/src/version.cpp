namespace cleanslam::drivers {

const char* version() {
  return "0.1.0";
}

}  // namespace cleanslam::drivers
