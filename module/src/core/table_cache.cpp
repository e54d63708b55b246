// The disk cache of the tables of the light scattered more than once (see the header).
#include "table_cache.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <system_error>

#include <unistd.h>

namespace aerial::detail {
namespace {

namespace fs = std::filesystem;

/// The first line of every file; a new layout takes a new version.
constexpr const char* kMagic = "aerial multiple-scattering table 1";

std::string hex(double x) {
    char text[40];
    std::snprintf(text, sizeof text, "%a", x);
    return text;
}

std::string hex(const glm::dvec3& v) { return hex(v.x) + "," + hex(v.y) + "," + hex(v.z); }

const char* environment(const char* name) {
    const char* value = std::getenv(name);
    return value && *value ? value : nullptr;
}

/// The cache directory, or empty when the cache is off.
fs::path cache_directory() {
    if (const char* off = environment("AERIAL_CACHE_DISABLE")) {
        if (std::strcmp(off, "0") != 0) return {};
    }
    if (const char* dir = environment("AERIAL_CACHE_DIR")) return dir;
    if (const char* xdg = environment("XDG_CACHE_HOME")) return fs::path(xdg) / "aerial";
    if (const char* home = environment("HOME")) return fs::path(home) / ".cache" / "aerial";
    return {};
}

/// FNV-1a, 64 bits: the file name of a key (the key itself is in the file and compared).
std::string file_name(const std::string& key) {
    unsigned long long h = 1469598103934665603ull;
    for (unsigned char c : key) {
        h ^= c;
        h *= 1099511628211ull;
    }
    char text[32];
    std::snprintf(text, sizeof text, "%016llx.table", h);
    return text;
}

template <class T>
bool read_value(std::istream& in, T& value) {
    return bool(in.read(reinterpret_cast<char*>(&value), sizeof value));
}

template <class T>
void write_value(std::ostream& out, const T& value) {
    out.write(reinterpret_cast<const char*>(&value), sizeof value);
}

/// The cache's size limit: $AERIAL_CACHE_MAX_MB megabytes when that is a whole number above 0,
/// else kMaxCacheBytes.
unsigned long long max_cache_bytes() {
    if (const char* text = environment("AERIAL_CACHE_MAX_MB")) {
        char* end = nullptr;
        const unsigned long long mb = std::strtoull(text, &end, 10);
        if (end && *end == '\0' && mb > 0 && mb < (1ull << 40)) return mb << 20;
    }
    return kMaxCacheBytes;
}

/// Removes the least recently used tables (by their time stamps, which a read renews) while the
/// directory holds more than max_cache_bytes().
void trim(const fs::path& dir) {
    std::error_code ec;
    std::vector<std::pair<fs::file_time_type, fs::path>> files;
    unsigned long long total = 0;
    for (const auto& entry : fs::directory_iterator(dir, ec)) {
        if (entry.path().extension() != ".table") continue;
        const auto size = entry.file_size(ec);
        const auto time = entry.last_write_time(ec);
        if (ec) continue;
        total += size;
        files.emplace_back(time, entry.path());
    }
    std::sort(files.begin(), files.end());
    for (const auto& file : files) {
        if (total <= max_cache_bytes()) break;
        const auto size = fs::file_size(file.second, ec);
        if (fs::remove(file.second, ec)) total -= ec ? 0 : size;
    }
}

}  // namespace

std::string table_cache_key(const Atmosphere& a, const MultipleScatteringSettings& s) {
    std::string key = "rayleigh_scattering " + hex(a.rayleigh_scattering);
    key += " mie_scattering " + hex(a.mie_scattering) + " mie_absorption " + hex(a.mie_absorption);
    key += " mie_g " + hex(a.mie_g) + " rayleigh_scale_height_m " + hex(a.rayleigh_scale_height_m);
    key += " mie_scale_height_m " + hex(a.mie_scale_height_m);
    key += " ozone_absorption " + hex(a.ozone_absorption);
    key += " ozone_center_altitude_m " + hex(a.ozone_center_altitude_m);
    key += " ozone_width_m " + hex(a.ozone_width_m);
    key += " planet_radius_m " + hex(a.planet_radius_m);
    key += " atmosphere_radius_m " + hex(a.atmosphere_radius_m);
    key += " ground_albedo " + hex(a.ground_albedo);
    key += " altitudes " + std::to_string(s.altitudes);
    key += " sun_zenith_angles " + std::to_string(s.sun_zenith_angles);
    key += " view_zenith_angles " + std::to_string(s.view_zenith_angles);
    key += " azimuths " + std::to_string(s.azimuths);
    key += " sky_directions " + std::to_string(s.sky_directions);
    key += " ground_directions " + std::to_string(s.ground_directions);
    key += " half_azimuths " + std::to_string(s.half_azimuths);
    key += " steps_per_efold " + hex(s.steps_per_efold);
    key += " max_remainder " + hex(s.max_remainder);
    key += " max_orders " + std::to_string(s.max_orders);
    return key;
}

bool load_cached_table(const std::string& key, std::size_t size, std::vector<glm::dvec3>& density,
                       MultipleScatteringReport& report) {
    const fs::path dir = cache_directory();
    if (dir.empty()) return false;
    std::ifstream in(dir / file_name(key), std::ios::binary);
    std::string magic, stored_key;
    if (!in || !std::getline(in, magic) || magic != kMagic || !std::getline(in, stored_key) ||
        stored_key != key) {
        return false;
    }
    MultipleScatteringReport r;
    std::uint64_t orders = 0, sums = 0, entries = 0;
    if (!read_value(in, orders) || !read_value(in, r.remainder_bound) ||
        !read_value(in, r.seconds) || !read_value(in, sums) || sums > 100000) {
        return false;
    }
    r.orders = int(orders);
    r.order_sums.resize(sums);
    for (glm::dvec3& sum : r.order_sums) {
        if (!read_value(in, sum)) return false;
    }
    if (!read_value(in, entries) || entries != size) return false;
    std::vector<glm::dvec3> table(size);
    if (!in.read(reinterpret_cast<char*>(table.data()),
                 std::streamsize(size * sizeof(glm::dvec3)))) {
        return false;
    }
    for (const glm::dvec3& v : table) {
        if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z)) return false;
    }
    density = std::move(table);
    report = std::move(r);
    report.from_cache = true;
    // A read renews the file's time stamp: the trim removes the least recently used.
    std::error_code ec;
    fs::last_write_time(dir / file_name(key), fs::file_time_type::clock::now(), ec);
    return true;
}

void store_cached_table(const std::string& key, const std::vector<glm::dvec3>& density,
                        const MultipleScatteringReport& report) {
    const fs::path dir = cache_directory();
    if (dir.empty()) return;
    std::error_code ec;
    fs::create_directories(dir, ec);
    const fs::path target = dir / file_name(key);
    const fs::path temporary =
        dir / (file_name(key) + "." + std::to_string(long(::getpid())) + ".partial");
    {
        std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
        if (!out) return;
        out << kMagic << '\n' << key << '\n';
        write_value(out, std::uint64_t(report.orders));
        write_value(out, report.remainder_bound);
        write_value(out, report.seconds);
        write_value(out, std::uint64_t(report.order_sums.size()));
        for (const glm::dvec3& sum : report.order_sums) write_value(out, sum);
        write_value(out, std::uint64_t(density.size()));
        out.write(reinterpret_cast<const char*>(density.data()),
                  std::streamsize(density.size() * sizeof(glm::dvec3)));
        if (!out.flush()) {
            out.close();
            fs::remove(temporary, ec);
            return;
        }
    }
    fs::rename(temporary, target, ec);
    if (ec) {
        fs::remove(temporary, ec);
        return;
    }
    trim(dir);
}

}  // namespace aerial::detail
