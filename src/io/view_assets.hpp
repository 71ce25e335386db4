#pragma once
// The texts the viewer's pages are made of, built into the library (the build generates their
// definitions from src/io/viewer/ and Debian's three.js, see CMakeLists.txt), so that the
// program needs no file at run time and the pages load nothing.
#include <string_view>

namespace stiffmsa::detail {

std::string_view three_js();           // three.js r111 (libjs-three)
std::string_view orbit_controls_js();  // its examples/js/controls/OrbitControls.js
std::string_view viewer_css();
std::string_view model_view_template();  // HTML with the markers page_from_template() fills
std::string_view model_view_js();
std::string_view sweep_view_template();
std::string_view sweep_view_js();

}  // namespace stiffmsa::detail
