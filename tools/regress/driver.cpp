// Driver selection and identity (driver.hpp).
#include "regress/driver.hpp"

#include <cstdlib>
#include <cstring>

extern char** environ;

namespace aerial::regress {

namespace {

// The prefixes of the variables that choose a driver or change what it offers.
constexpr const char* kMesaPrefixes[] = {"GALLIUM_",     "MESA_",  "LIBGL_",
                                         "LP_",          "ZINK_",  "EGL_PLATFORM",
                                         "__EGL_VENDOR", "VK_ICD", "XDG_RUNTIME"};

}  // namespace

Environment driver_variables(headless::Platform platform, const std::string& driver) {
    if (driver.empty()) return {};
    Environment vars{{"GALLIUM_DRIVER", driver}};
    if (driver == "zink" && platform == headless::Platform::egl) {
        vars.emplace_back("LIBGL_ALWAYS_SOFTWARE", "1");
    }
    return vars;
}

Result<std::vector<std::string>> apply_environment(const Environment& driver_vars,
                                                   const Environment& suite_vars) {
    for (const auto& [name, value] : driver_vars) {
        const char* set = std::getenv(name.c_str());
        if (set != nullptr && value != set) {
            return Error{"--driver", "--driver: the environment has " + name + "=" + set +
                                         ", the driver asked for needs " + name + "=" + value +
                                         "; unset it or ask for that driver"};
        }
        setenv(name.c_str(), value.c_str(), 1);
    }
    for (const auto& [name, value] : suite_vars) {
        if (std::getenv(name.c_str()) == nullptr) setenv(name.c_str(), value.c_str(), 1);
    }
    return mesa_variables();
}

std::vector<std::string> mesa_variables() {
    std::vector<std::string> vars;
    for (char** e = environ; e != nullptr && *e != nullptr; ++e) {
        for (const char* prefix : kMesaPrefixes) {
            if (std::strncmp(*e, prefix, std::strlen(prefix)) == 0) {
                vars.emplace_back(*e);
                break;
            }
        }
    }
    return vars;
}

std::string driver_mismatch(const std::string& driver, const std::string& renderer) {
    if (driver.empty()) return {};
    const std::string reported = headless::renderer_driver(renderer);
    if (reported == driver) return {};
    std::string why =
        "GL_RENDERER is '" + renderer + "', not the driver asked for (" + driver + ")";
    for (const char* name : {"MESA_LOADER_DRIVER_OVERRIDE", "LIBGL_ALWAYS_SOFTWARE"}) {
        if (const char* v = std::getenv(name))
            why += "; " + std::string(name) + "=" + v + " is set";
    }
    return why;
}

std::string device_name(headless::Platform platform, const std::string& renderer) {
    return std::string(headless::platform_name(platform)) + "-" +
           headless::renderer_driver(renderer);
}

}  // namespace aerial::regress
