#include "studies/journal.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cinttypes>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "framework/atomic_file.h"
#include "framework/error.h"
#include "robot/robot_file.h"

namespace kincal {
namespace {

// The format's version changes whenever the rows a record holds change (a table gains a column): a
// journal of another version is refused, never mixed in.
const char kMagicPrefix[] = "kincal study journal v";
const char kMagic[] = "kincal study journal v2 ";

std::string Hex(uint64_t v) {
  char buffer[20];
  std::snprintf(buffer, sizeof(buffer), "%016" PRIx64, v);
  return buffer;
}

std::string SystemError(const std::string& path, const std::string& what) {
  return path + ": " + what + ": " + std::strerror(errno);
}

void WriteAll(int fd, const std::string& text, const std::string& path) {
  size_t done = 0;
  while (done < text.size()) {
    const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) ThrowIoError(path, "cannot write the journal");
    done += static_cast<size_t>(n);
  }
}

// So that a new journal's name survives a power cut, not only its content.
void SyncFolder(const std::string& dir) {
  const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY);
  if (fd < 0) return;
  ::fsync(fd);
  ::close(fd);
}

ResultTable* Table(StudyTables& t, int i) { return t.All()[i]; }

// The journal's first line against the header this run writes: another version's, another file's or
// another study's journal is refused, never mixed in.
void CheckJournalHeader(const std::string& path, const std::string& first, const std::string& fingerprint) {
  if (first.rfind(kMagicPrefix, 0) == 0 && first.rfind(kMagic, 0) != 0) {
    ThrowInputError(
        path + ": a journal of another kincal version (" + first.substr(0, first.find(' ', sizeof(kMagicPrefix))) +
        ", this one writes " + std::string(kMagic, sizeof(kMagic) - 2) +
        "); its results are not mixed in: choose another --out folder, or delete the journal to start over");
  }
  if (first.rfind(kMagic, 0) != 0) {
    ThrowInputError(path + ": not a kincal study journal; remove it or choose another --out folder");
  }
  if (first != kMagic + fingerprint) {
    ThrowInputError(path + ": written by a different study or shard (journal " + first.substr(sizeof(kMagic) - 1) +
                    ", this run " + fingerprint +
                    "); its results are not mixed in: choose another --out folder, "
                    "or delete the journal to start over");
  }
}

}  // namespace

std::string EncodeJournalRows(const StudyTables& rows) {
  nlohmann::json j = nlohmann::json::array();
  StudyTables copy = rows;
  for (int i = 0; i < StudyTables::kCount; ++i) j.push_back(Table(copy, i)->rows);
  return j.dump();  // one line: strings escape their control characters
}

StudyTables DecodeJournalRows(const std::string& payload) {
  StudyTables t;
  try {
    const nlohmann::json j = nlohmann::json::parse(payload);
    if (!j.is_array() || j.size() != StudyTables::kCount) {
      throw std::invalid_argument("expected " + std::to_string(StudyTables::kCount) + " tables");
    }
    for (int i = 0; i < StudyTables::kCount; ++i) Table(t, i)->rows = j[i].get<std::vector<std::vector<std::string>>>();
  } catch (const nlohmann::json::exception& e) {
    throw std::invalid_argument(e.what());
  }
  return t;
}

std::string StudyFingerprint(const Study& study, int shard_index, int shard_count) {
  std::string text = std::to_string(study.text_hash) + "\n";
  text +=
      StudyManifest(study, Variants(study), static_cast<int>(WorkItems(study, Variants(study)).size())).dump() + "\n";
  text += RobotToYaml(study.nominal.robot) + "\n";
  if (study.truth) text += RobotToYaml(study.truth->robot) + "\n";
  for (const DatasetSpec& d : study.datasets) {
    if (!d.simulated) text += Hex(HashLabel(ReadFileToString(d.file))) + "\n";
    for (const auto& [marker, path] : d.position_tables)
      text += marker + " " + Hex(HashLabel(ReadFileToString(path))) + "\n";
    if (!d.sequence_table.empty()) text += "sequence " + Hex(HashLabel(ReadFileToString(d.sequence_table))) + "\n";
  }
  return Hex(HashLabel(text)) + "/shard-" + std::to_string(shard_index) + "-of-" + std::to_string(shard_count);
}

StudyJournal::StudyJournal(const std::string& dir, const std::string& fingerprint, int items)
    : path_(dir + "/" + kFileName) {
  std::filesystem::create_directories(dir);
  const bool existed = std::filesystem::exists(path_);
  fd_ = ::open(path_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd_ < 0) ThrowInputError(SystemError(path_, "cannot open the study journal"));
  if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    ::close(fd_);
    fd_ = -1;
    ThrowInputError(path_ + ": locked: another kincal study is running on " + dir);
  }
  try {
    const std::string text = ReadFileToString(path_);
    const std::string header = kMagic + fingerprint + "\n";
    size_t valid = 0;  // bytes of whole records
    if (text.size() >= header.size() || (!text.empty() && text.back() == '\n')) {
      CheckJournalHeader(path_, text.substr(0, text.find('\n')), fingerprint);
      valid = ReadRecords(text, header.size(), items);
    }
    if (valid == 0) {  // new, empty or torn within its header
      if (::ftruncate(fd_, 0) != 0) ThrowIoError(path_, "cannot truncate the journal");
      discarded_bytes_ = static_cast<long>(text.size());
      ::lseek(fd_, 0, SEEK_SET);
      WriteAll(fd_, header, path_);
      if (::fsync(fd_) != 0) ThrowIoError(path_, "cannot sync the journal");
      if (!existed) SyncFolder(dir);
    } else if (valid < text.size()) {
      discarded_bytes_ = static_cast<long>(text.size() - valid);
      if (::ftruncate(fd_, static_cast<off_t>(valid)) != 0 || ::fsync(fd_) != 0) {
        ThrowIoError(path_, "cannot truncate the torn end of the journal");
      }
    }
    ::lseek(fd_, 0, SEEK_END);
  } catch (...) {
    ::close(fd_);
    fd_ = -1;
    throw;
  }
}

// Reads the whole records of text from byte from on into recorded_; returns the bytes they end at (a torn
// last record is left out; a damaged one before it is an error).
size_t StudyJournal::ReadRecords(const std::string& text, size_t from, int items) {
  size_t valid = from;
  while (valid < text.size()) {
    const size_t line_end = text.find('\n', valid);
    int item = -1;
    unsigned long long bytes = 0;
    char checksum[17] = {0};
    int consumed = 0;
    const std::string head =
        text.substr(valid, line_end == std::string::npos ? std::string::npos : line_end - valid);
    if (std::sscanf(head.c_str(), "item %d %llu %16s %n", &item, &bytes, checksum, &consumed) != 3 ||
        consumed <= 0) {
      if (line_end == std::string::npos) break;  // torn in its first bytes
      ThrowInputError(path_ + ": damaged record at byte " + std::to_string(valid));
    }
    const size_t payload_at = valid + static_cast<size_t>(consumed);
    if (payload_at + bytes + 1 > text.size()) break;  // torn: cut short
    const std::string payload = text.substr(payload_at, bytes);
    const bool whole = text[payload_at + bytes] == '\n' && Hex(HashLabel(payload)) == checksum;
    if (!whole) {
      if (payload_at + bytes + 1 == text.size()) break;  // the last record: torn
      ThrowInputError(path_ + ": damaged record at byte " + std::to_string(valid) + " (checksum)");
    }
    if (item < 0 || item >= items) {
      ThrowInputError(path_ + ": record at byte " + std::to_string(valid) + " names work item " +
                      std::to_string(item) + " of a study of " + std::to_string(items));
    }
    try {
      recorded_[item] = DecodeJournalRows(payload);
    } catch (const std::invalid_argument& e) {
      ThrowInputError(path_ + ": damaged record at byte " + std::to_string(valid) + ": " + e.what());
    }
    valid = payload_at + bytes + 1;
  }
  return valid;
}

StudyJournal::~StudyJournal() {
  if (fd_ >= 0) ::close(fd_);
}

void StudyJournal::Append(int item, const StudyTables& rows) {
  const std::string payload = EncodeJournalRows(rows);
  const std::string record = "item " + std::to_string(item) + " " + std::to_string(payload.size()) + " " +
                             Hex(HashLabel(payload)) + " " + payload + "\n";
  std::lock_guard<std::mutex> lock(mutex_);
  WriteAll(fd_, record, path_);
  if (::fdatasync(fd_) != 0) ThrowIoError(path_, "cannot sync the journal");
}

}  // namespace kincal
