namespace cleanslam::firmware {

const char* version() {
  return "0.1.0";
}

}  // namespace cleanslam::firmware
