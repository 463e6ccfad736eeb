#pragma once
// The memory budget: every buffer whose size the input decides (film and AOVs, raster sample
// buffers, mesh arrays, photon maps) is estimated and checked here before it is allocated, so
// that an impossible request stops at once with a message (exit code 2) instead of being
// killed by the kernel after minutes of swapping.
//
// The budget is what the machine can still give (MemAvailable in /proc/meminfo), capped by
// --max-memory (set_memory_limit) less what the process already holds (its resident set).
// Each request is checked on its own against what is available when it is made.

#include "core/error.h"

#include <cstdint>
#include <string>

namespace candela {

// The --max-memory cap in bytes (0: none).
void set_memory_limit(uint64_t bytes);
uint64_t memory_limit();

// What the process holds now (its resident set), 0 when unknown.
uint64_t resident_memory();

// Bytes that may still be allocated: MemAvailable, and under a cap, the cap less the resident
// set. UINT64_MAX when neither is known.
uint64_t memory_available();

// Stops the run if `bytes` exceed memory_available(): a SceneError at `where` (the scene element
// that asked for the memory), or an InputError when `where` names no file, with the message
// "<what> needs 190 GB; 6.1 GB available" ("...; 3.2 GB available under --max-memory 4 GB"
// when the cap decides). Both give exit code 2.
void check_memory(uint64_t bytes, const std::string& what, const SourceLocation& where = {});

// Products and sums of sizes that saturate at UINT64_MAX instead of wrapping around, for
// estimates from untrusted counts.
uint64_t saturating_mul(uint64_t a, uint64_t b);
uint64_t saturating_add(uint64_t a, uint64_t b);

// "190 GB", "6.1 GB", "512 MB", "12 kB", "100 B", in powers of 1024 as --max-memory reads them.
std::string format_bytes(uint64_t bytes);
// "4G", "512M", "1.5G", "64k", "1000000" (bytes); suffixes k, M, G, T are powers of 1024, with
// an optional trailing "B" or "iB". Throws InputError for anything else, or for zero.
uint64_t parse_memory_size(const std::string& text);

}  // namespace candela
