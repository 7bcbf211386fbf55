#pragma once
// Facts about this run's host and moment, recorded with every run and batch (results database, batch
// store, Slurm jobs): one implementation for all of them.
#include <string>

namespace dash {

/// A random RFC 4122 version 4 UUID, "xxxxxxxx-xxxx-4xxx-[89ab]xxx-xxxxxxxxxxxx" (lowercase hex).
std::string newUuid();
/// This machine's host name, or "unknown".
std::string hostName();
/// The current UTC time in strftime `format` (default ISO 8601: "2026-11-28T01:45:00Z").
std::string utcNow(const char* format = "%Y-%m-%dT%H:%M:%SZ");

}  // namespace dash
