namespace facet::render {
const char* version() {
    return "0.1.0";
}
}  // namespace facet::render
