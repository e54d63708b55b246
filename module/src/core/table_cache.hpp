// Internal: the disk cache of the tables of the light scattered more than once (docs/models.md,
// "Table cache"). A table costs from a fraction of a second (the `height` model's) to seconds (the
// `reference`'s) per atmosphere; processes that start often (a regression harness's children, a
// tool run per image) would pay that every time. Like Mesa's shader cache, the tables are kept
// in a per-user directory:
//   $AERIAL_CACHE_DIR, else $XDG_CACHE_HOME/aerial, else $HOME/.cache/aerial;
//   AERIAL_CACHE_DISABLE set to anything but "" or "0" turns the cache off.
// A file holds its key (every input of the table, exactly) and the table in this machine's byte
// order; one that does not match, is short or is unreadable is ignored and recomputed. Files are
// written to a temporary name and renamed, so concurrent processes never read half a file; the
// least recently used files go when the directory passes kMaxCacheBytes ($AERIAL_CACHE_MAX_MB
// sets another limit). Nothing here is ever an error: a cache that cannot be read or written is
// a cache miss.
#pragma once

#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "aerial/atmosphere.hpp"
#include "aerial/scattering.hpp"

namespace aerial::detail {

/// The cache directory's size above which the least recently used files are removed (unless
/// $AERIAL_CACHE_MAX_MB sets another).
inline constexpr unsigned long long kMaxCacheBytes = 256ull << 20;

/// Every input of a table, exactly (hexadecimal floats): the atmosphere without its
/// sun_irradiance (the tables are per unit E_sun0) and the settings.
std::string table_cache_key(const Atmosphere& atmosphere,
                            const MultipleScatteringSettings& settings);

/// Reads the table of `key`: true and `density` (of exactly `size` entries) and `report` filled
/// when the cache holds it.
bool load_cached_table(const std::string& key, std::size_t size, std::vector<glm::dvec3>& density,
                       MultipleScatteringReport& report);

/// Writes the table of `key` (silently nothing when the cache is off or not writable).
void store_cached_table(const std::string& key, const std::vector<glm::dvec3>& density,
                        const MultipleScatteringReport& report);

}  // namespace aerial::detail
