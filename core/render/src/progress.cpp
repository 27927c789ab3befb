// Progress bar / quiet log; see facet/render/progress.h.
#include "facet/render/progress.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>

namespace facet::render {

std::string format_duration(double s) {
    char buf[32];
    if (!(s >= 0) || !std::isfinite(s)) return "?";
    if (s < 60) {
        std::snprintf(buf, sizeof buf, "%.1fs", s);
    } else if (s < 3600) {
        std::snprintf(buf, sizeof buf, "%dm%02ds", int(s) / 60, int(s) % 60);
    } else {
        std::snprintf(buf, sizeof buf, "%dh%02dm", int(s) / 3600, (int(s) % 3600) / 60);
    }
    return buf;
}

Progress::Progress(std::string label, std::uint64_t total, Mode mode, std::FILE* out)
    : m_label(std::move(label)),
      m_total(total),
      m_mode(mode),
      m_out(out),
      m_start(std::chrono::steady_clock::now()) {
    if (m_mode == Mode::Auto) m_mode = (out && isatty(fileno(out))) ? Mode::Bar : Mode::Log;
    if (!m_out) m_mode = Mode::Silent;
    if (m_mode == Mode::Log) {
        std::fprintf(m_out, "%s: started\n", m_label.c_str());
        std::fflush(m_out);
    }
}

Progress::~Progress() {
    if (m_mode == Mode::Bar && !m_finished) {
        std::fputc('\n', m_out);
        std::fflush(m_out);
    }
}

double Progress::elapsed_s() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - m_start).count();
}

void Progress::add(std::uint64_t work) {
    m_done.fetch_add(work, std::memory_order_relaxed);
    if (m_mode != Mode::Bar) return;
    const auto now_ms = std::int64_t(elapsed_s() * 1000.0);
    if (now_ms - m_last_draw_ms.load(std::memory_order_relaxed) < 100) return;
    std::unique_lock lock(m_draw_mutex, std::try_to_lock);
    if (!lock.owns_lock()) return;
    m_last_draw_ms.store(now_ms, std::memory_order_relaxed);
    draw(false);
}

void Progress::draw(bool final_line) {
    const double t = elapsed_s();
    const std::uint64_t total = m_total.load(std::memory_order_relaxed);
    const std::uint64_t done = m_done.load(std::memory_order_relaxed);
    double frac = 0;
    if (m_budget_s > 0)
        frac = std::min(1.0, t / m_budget_s);
    else if (total > 0)
        frac = std::min(1.0, double(done) / double(total));
    if (final_line) frac = 1.0;
    constexpr int kWidth = 40;
    const int filled = int(frac * kWidth);
    char bar[kWidth + 1];
    for (int i = 0; i < kWidth; ++i) bar[i] = i < filled ? '#' : '-';
    bar[kWidth] = '\0';
    const double eta = frac > 0 ? t * (1.0 - frac) / frac : -1.0;
    std::fprintf(m_out, "\r%s [%s] %5.1f%%  elapsed %s  ETA %s   ", m_label.c_str(), bar,
                 100.0 * frac, format_duration(t).c_str(),
                 final_line ? "0.0s" : format_duration(eta).c_str());
    std::fflush(m_out);
}

void Progress::finish(const std::string& summary) {
    std::lock_guard lock(m_draw_mutex);
    if (m_finished) return;
    m_finished = true;
    if (m_mode == Mode::Bar) {
        draw(true);
        std::fputc('\n', m_out);
        if (!summary.empty()) std::fprintf(m_out, "%s\n", summary.c_str());
    } else if (m_mode == Mode::Log) {
        std::fprintf(m_out, "%s: done in %s%s%s\n", m_label.c_str(),
                     format_duration(elapsed_s()).c_str(), summary.empty() ? "" : "; ",
                     summary.c_str());
    }
    if (m_out) std::fflush(m_out);
}

}  // namespace facet::render
