// Progress reporting for long renders: a bar with ETA on a terminal, quiet logs otherwise.
//
// Conventions:
//  - Work is counted in abstract units (the renderer uses pixel samples). add() is thread safe
//    and cheap (one relaxed atomic add and a clock read); callers call it per tile, never per
//    sample. Drawing happens from whichever thread holds a try-lock, at most every 100 ms.
//  - Mode::Auto draws a bar on stderr when stderr is a terminal (isatty) and otherwise prints
//    one line when the work starts and one summary line at finish(); Mode::Silent prints nothing.
//  - For time-budget renders the total is unknown: set_time_budget() makes the bar show the
//    elapsed fraction of the budget instead.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <mutex>
#include <string>

namespace facet::render {

class Progress {
  public:
    enum class Mode { Auto, Bar, Log, Silent };

    Progress(std::string label, std::uint64_t total, Mode mode, std::FILE* out = stderr);
    ~Progress();
    Progress(const Progress&) = delete;
    Progress& operator=(const Progress&) = delete;

    void set_time_budget(double seconds) { m_budget_s = seconds; }
    void set_total(std::uint64_t total) { m_total.store(total, std::memory_order_relaxed); }
    void add(std::uint64_t work);
    // Prints the final state (bar at 100% and a newline, or the summary log line). Idempotent.
    void finish(const std::string& summary = "");

    double elapsed_s() const;
    Mode mode() const { return m_mode; }

  private:
    void draw(bool final_line);

    std::string m_label;
    std::atomic<std::uint64_t> m_total;
    std::atomic<std::uint64_t> m_done{0};
    Mode m_mode;
    std::FILE* m_out;
    double m_budget_s = 0;
    std::chrono::steady_clock::time_point m_start;
    std::atomic<std::int64_t> m_last_draw_ms{-1000};
    std::mutex m_draw_mutex;
    bool m_finished = false;
};

// Formats seconds as "1h02m", "3m05s" or "4.2s".
std::string format_duration(double seconds);

}  // namespace facet::render
