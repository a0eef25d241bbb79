#pragma once
// The processes below this one, from /proc, for tests of the isolated readers
// (io/isolated_read.hpp): this process's children are its threads' reader hosts, and their
// children are the readers.
#include <algorithm>
#include <cctype>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <sys/types.h>
#include <unistd.h>

namespace prismoid::test {

struct ProcessStat {
  pid_t parent = 0;
  uint64_t cpu_ticks = 0;  // user + system time, in clock ticks
  int threads = 0;
};

// Every process on the machine that /proc shows, by pid.
inline std::map<pid_t, ProcessStat> process_table() {
  std::map<pid_t, ProcessStat> table;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator("/proc", ec)) {
    const std::string name = entry.path().filename().string();
    if (name.empty() || !std::all_of(name.begin(), name.end(), [](char c) { return std::isdigit(static_cast<unsigned char>(c)); })) continue;
    std::ifstream in(entry.path() / "stat");
    std::string stat;
    std::getline(in, stat);
    const size_t close = stat.rfind(')');  // the command's name may hold spaces and parentheses
    if (close == std::string::npos || close + 2 >= stat.size()) continue;
    std::istringstream fields(stat.substr(close + 2));
    std::string state;
    long long parent = 0, skip = 0, threads = 0;
    uint64_t utime = 0, stime = 0;
    fields >> state >> parent;
    for (int i = 0; i < 9; ++i) fields >> skip;  // pgrp .. cmajflt
    fields >> utime >> stime;
    for (int i = 0; i < 4; ++i) fields >> skip;  // cutime .. nice
    fields >> threads;
    if (fields) table[pid_t(std::atoll(name.c_str()))] = {pid_t(parent), utime + stime, int(threads)};
  }
  return table;
}

// The children of `parent` in `table`.
inline std::vector<pid_t> children_in(const std::map<pid_t, ProcessStat>& table, pid_t parent) {
  std::vector<pid_t> children;
  for (const auto& [pid, stat] : table)
    if (stat.parent == parent) children.push_back(pid);
  return children;
}

// The readers running now: this process's grandchildren.
inline std::vector<pid_t> running_readers(const std::map<pid_t, ProcessStat>& table = process_table()) {
  std::vector<pid_t> readers;
  for (const pid_t host : children_in(table, ::getpid()))
    for (const pid_t reader : children_in(table, host)) readers.push_back(reader);
  return readers;
}

}  // namespace prismoid::test
