#include "cli/detection_plot.h"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "io/atomic_file.h"

namespace quadfdi::cli {
namespace {

std::string shellQuote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

// gnuplot single-quoted string: only ' needs doubling.
std::string gpQuote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("''") : std::string(1, c);
  return q + "'";
}

bool run(const std::string& command) { return std::system(command.c_str()) == 0; }

class TempDir {
 public:
  TempDir() {
    const char* base = std::getenv("TMPDIR");
    std::string pattern = std::string(base && *base ? base : "/tmp") + "/quadfdi-plot-XXXXXX";
    std::vector<char> buf(pattern.begin(), pattern.end());
    buf.push_back('\0');
    if (!mkdtemp(buf.data())) throw std::runtime_error(pattern + ": cannot create a temporary folder for the plot");
    path_ = buf.data();
  }
  ~TempDir() {
    std::remove((path_ + "/detections.dat").c_str());
    std::remove((path_ + "/detections.gp").c_str());
    std::remove((path_ + "/detections.png").c_str());
    rmdir(path_.c_str());
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

}  // namespace

void requireGnuplot() {
  if (!run("command -v gnuplot >/dev/null 2>&1"))
    throw std::runtime_error("--plot needs gnuplot, which is not on the PATH (Debian: apt-get install gnuplot-nox)");
}

void plotDetections(const DetectionPlotData& d, const std::string& png_path) {
  requireGnuplot();
  TempDir dir;
  const std::string dat = dir.path() + "/detections.dat", gp = dir.path() + "/detections.gp",
                    png = dir.path() + "/detections.png";
  {
    std::ofstream out(dat);
    out << "# t theta1 theta2 theta3 theta4 alarm motor\n";
    double last = 0.0;
    for (std::size_t i = 0; i < d.outputs.size(); ++i) {
      const DetectorOutput& o = d.outputs[i];
      if (i > 0 && o.t - last > d.max_gap) out << "\n";  // break the lines across skipped stretches
      last = o.t;
      char b[160];
      std::snprintf(b, sizeof b, "%.6f %.4f %.4f %.4f %.4f %d %d\n", o.t, static_cast<double>(o.theta[0]),
                    static_cast<double>(o.theta[1]), static_cast<double>(o.theta[2]), static_cast<double>(o.theta[3]),
                    o.alarm ? 1 : 0, o.motor);
      out << b;
    }
    if (!out) throw std::runtime_error(dat + ": write failed");
  }
  const bool cairo = run("gnuplot -e 'set terminal pngcairo' >/dev/null 2>&1");
  std::ostringstream s;
  s << (cairo ? "set terminal pngcairo size 1200,560 font 'DejaVu Sans,10'\n" : "set terminal png size 1200,560\n");
  s << "set output " << gpQuote(png) << "\n";
  s << "set title " << gpQuote(d.title) << " noenhanced\n";
  s << "set xlabel 't [s]'\nset ylabel 'estimated effectiveness per motor'\nset yrange [-0.05:1.15]\nset grid\n";
  s << "set key outside right top\n";
  int n = 1;
  // Evaluated phases: a light band; alarm intervals: red, over it.
  for (const PlotPhase& p : d.phases)
    s << "set object " << n++ << " rect from " << p.begin << ", graph 0 to " << p.end
      << ", graph 1 fc rgb '#e6f0ff' fs solid 1.0 noborder behind\n";
  double first_alarm = -1.0;
  int first_motor = 0;
  for (std::size_t i = 0; i < d.outputs.size();) {
    if (!d.outputs[i].alarm) {
      ++i;
      continue;
    }
    const std::size_t a = i;
    while (i < d.outputs.size() && d.outputs[i].alarm && (i == a || d.outputs[i].t - d.outputs[i - 1].t <= d.max_gap)) ++i;
    if (first_alarm < 0.0) {
      first_alarm = d.outputs[a].t;
      first_motor = d.outputs[a].motor;
    }
    s << "set object " << n++ << " rect from " << d.outputs[a].t << ", graph 0 to " << d.outputs[i - 1].t
      << ", graph 1 fc rgb '#ff9999' fs transparent solid 0.45 noborder\n";
  }
  if (first_alarm >= 0.0) {
    s << "set arrow 1 from " << first_alarm << ", graph 0 to " << first_alarm << ", graph 1 nohead lc rgb '#c00000' lw 2 dt 2\n";
    char label[128];
    std::snprintf(label, sizeof label, "first alarm: motor %d at t = %.3f s", first_motor, first_alarm);
    s << "set label 1 " << gpQuote(label) << " at " << first_alarm << ", graph 0.96 left offset 0.6,0 tc rgb '#c00000' front noenhanced\n";
  } else {
    s << "set label 1 'no alarm' at graph 0.02, graph 0.96 left front\n";
  }
  // Legend entries for the shading (empty plots with the right style).
  s << "plot ";
  const char* colours[] = {"#1f77b4", "#ff7f0e", "#2ca02c", "#9467bd"};
  for (int k = 0; k < 4; ++k)
    s << (k ? ", " : "") << gpQuote(dat) << " using 1:" << k + 2 << " with lines lw 1.5 lc rgb '" << colours[k]
      << "' title 'motor " << k + 1 << "'";
  s << ", NaN with boxes fs solid 1.0 lc rgb '#e6f0ff' title 'evaluated phase'";
  s << ", NaN with boxes fs solid 0.45 lc rgb '#ff9999' title 'alarm'\n";
  {
    std::ofstream out(gp);
    out << s.str();
    if (!out) throw std::runtime_error(gp + ": write failed");
  }
  if (!run("gnuplot " + shellQuote(gp) + " 2>" + shellQuote(dir.path() + "/gnuplot.err"))) {
    std::ifstream err(dir.path() + "/gnuplot.err");
    std::string first;
    std::getline(err, first);
    std::remove((dir.path() + "/gnuplot.err").c_str());
    throw std::runtime_error(png_path + ": gnuplot failed" + (first.empty() ? "" : ": " + first));
  }
  std::remove((dir.path() + "/gnuplot.err").c_str());
  std::ifstream in(png, std::ios::binary);
  if (!in.is_open()) throw std::runtime_error(png_path + ": gnuplot wrote no image");
  AtomicFileWriter w(png_path);
  w.stream() << in.rdbuf();
  w.commit();
}

}  // namespace quadfdi::cli
