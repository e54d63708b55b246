// Builds without GLFW: no interactive window (main() says so for --window).
#include "game.hpp"

namespace sample {

bool window_available() { return false; }

int run_window(const World&, GameConfig, int, const std::string&) { return 2; }

}  // namespace sample
