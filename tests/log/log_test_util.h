#pragma once
// Shared by the engine/log tests: a temporary folder, and a scripted planner event stream.
#include <string>

#include "engine/events/event_emitter.h"
#include "engine/events/memory_sink.h"
#include "engine/log/results_db.h"
#include "engine/log/sqlite_recorder.h"
#include "tests/common/temp_dir.h"

namespace dash::log::testing {

using test::TempDir;

RunMetadata sampleMeta(const std::string& family = "sorting", const std::string& params = R"({"robots":2,"objects":4})",
                       const std::string& planner = "lazy-dash", std::uint64_t seed = 1);

/// A deterministic stream shaped like a planner's: per iteration, task vertices and hyperarcs,
/// extended-layer elements, constraints (some lifted), counters and phases. About 20 events per
/// iteration; `iterations` sets the size.
void emitScriptedRun(EventEmitter& emitter, int iterations);

/// beginRun, record the scripted stream (also into `mirror` if given), finishRun as solved.
std::string recordRun(ResultsDb& db, const RunMetadata& meta, int iterations, MemorySink* mirror = nullptr);

/// sqlite3's PRAGMA integrity_check on a file, through a fresh connection.
std::string integrityCheck(const std::string& path);

}  // namespace dash::log::testing
