#pragma once
// The journal of a resumable study: `study.journal` in the output folder, one record per finished
// work item, appended, flushed and synced as each item finishes. Running the same study on the same folder
// again reads it back and runs only the items it lacks; the rows of a journaled item are the exact text cells
// the result tables get, so a stopped-and-resumed run writes the bytes of an uninterrupted one.
//
// Format (text, one record per line, so a torn write is visible):
//   kincal study journal v2 <fingerprint>\n
//   item <index> <payload bytes> <FNV-1a 64 of the payload, hex> <payload: JSON, one line>\n
// The fingerprint names the study (content of the study file, robots, measured data, shard); a journal with
// another fingerprint is refused, never mixed in. A record cut short by SIGKILL or a power cut can only be
// the last one: it is discarded (and truncated away) on open. A damaged record followed by others is an error.
// The journal is locked (flock) while open, so two runs never write the same folder.
#include <map>
#include <mutex>
#include <string>

#include "studies/results_files.h"

namespace kincal {

class StudyJournal {
 public:
  static constexpr const char* kFileName = "study.journal";

  // Opens (creates) DIR/study.journal; `fingerprint` is one line without spaces (StudyFingerprint).
  // `items` is the number of work items of the study: recorded indices must be below it.
  // Throws std::invalid_argument (one line naming the file) for a foreign, damaged or locked journal.
  StudyJournal(const std::string& dir, const std::string& fingerprint, int items);
  ~StudyJournal();
  StudyJournal(const StudyJournal&) = delete;
  StudyJournal& operator=(const StudyJournal&) = delete;

  // The rows of the items recorded by earlier runs, by item index (headers empty).
  const std::map<int, StudyTables>& recorded() const { return recorded_; }
  // Bytes of a torn last record that were discarded on open (0 when the journal was whole).
  long discarded_bytes() const { return discarded_bytes_; }
  const std::string& path() const { return path_; }

  // Appends one item's rows and syncs the file. Thread-safe. Throws std::runtime_error on a write error.
  void Append(int item, const StudyTables& rows);

 private:
  size_t ReadRecords(const std::string& text, size_t from, int items);
  std::string path_;
  int fd_ = -1;
  std::mutex mutex_;
  std::map<int, StudyTables> recorded_;
  long discarded_bytes_ = 0;
};

// The fingerprint of a run: FNV-1a 64 over the study file's text, the manifest, the robots (as robot files),
// the measured data files and the shard, as "<16 hex digits>/shard-i-of-N".
std::string StudyFingerprint(const Study& study, int shard_index, int shard_count);

// The rows of one item's tables as one line of JSON and back (the journal's payload).
std::string EncodeJournalRows(const StudyTables& rows);
// Throws std::invalid_argument when `payload` is not such a line.
StudyTables DecodeJournalRows(const std::string& payload);

}  // namespace kincal
