#include "field_views.h"

#include <algorithm>

#include "scratch.h"
#include "topotet/mesh_stream.h"

namespace topotet::ooc {
namespace {

constexpr std::size_t kRun = std::size_t{1} << 15;     // doubles buffered before a write
constexpr std::uint64_t kWindow = 4096;                 // entities read back at once

}  // namespace

void FieldViews::begin(const std::string& name, int components, std::uint64_t entities) {
  flush();
  if (!file_) file_.emplace(path_);
  entities_ = entities;
  View v{name, components, file_end_, true};
  file_end_ += entities * static_cast<std::uint64_t>(components) * sizeof(double);
  file_->resize(file_end_);  // sparse: the region reads 0 until written
  views_.push_back(v);
  run_.clear();
}

void FieldViews::values(std::uint64_t v, const double* values) {
  View& view = views_.back();
  const auto c = static_cast<std::size_t>(view.components);
  if (c == 9 && !is_symmetric_3x3(values)) view.symmetric = false;
  if (!run_.empty() && (v != run_first_ + run_.size() / c || run_.size() + c > kRun)) flush();
  if (run_.empty()) run_first_ = v;
  run_.insert(run_.end(), values, values + c);
}

void FieldViews::flush() {
  if (run_.empty()) return;
  const View& view = views_.back();
  file_->write_at(run_.data(), run_.size() * sizeof(double),
                  view.offset + run_first_ * static_cast<std::uint64_t>(view.components) * sizeof(double));
  run_.clear();
}

void FieldViews::finish(std::vector<std::int32_t>* vertex_refs) {
  flush();
  // One field per name: the first view's place, the last view's values.
  std::vector<const View*> last;
  for (const View& v : views_) {
    const auto same = std::find_if(last.begin(), last.end(), [&](const View* w) { return w->name == v.name; });
    if (same != last.end()) *same = &v;
    else last.push_back(&v);
  }
  for (const View* v : last) {
    if (vertex_refs != nullptr && v->name == kVertexRefField && v->components == 1) {
      // Integers: the vertex refs (io/gmsh.cpp's finish_fields), else an ordinary field.
      std::vector<std::int32_t> read_refs(entities_);
      std::vector<double> window(kWindow);
      bool integers = true;
      for (std::uint64_t first = 0; first < entities_ && integers; first += kWindow) {
        const std::size_t n = static_cast<std::size_t>(std::min(kWindow, entities_ - first));
        file_->read_at(window.data(), n * sizeof(double), v->offset + first * sizeof(double));
        for (std::size_t i = 0; i < n && integers; ++i) integers = exact_int32(window[i], read_refs[first + i]);
      }
      if (integers) {
        if (std::any_of(read_refs.begin(), read_refs.end(), [](std::int32_t x) { return x != 0; }))
          *vertex_refs = std::move(read_refs);
        continue;
      }
    }
    Window w;
    w.view = v;
    w.to_symmetric = v->components == 9 && v->symmetric;
    fields_.push_back({v->name, w.to_symmetric ? 6 : v->components});
    stride_ += fields_.back().components;
    windows_.push_back(std::move(w));
  }
}

void FieldViews::next(double* out) {
  const std::uint64_t v = next_++;
  const std::uint64_t first = v / kWindow * kWindow;
  for (Window& w : windows_) {
    const auto c = static_cast<std::size_t>(w.view->components);
    if (v == first || w.buffer.empty()) {
      const std::size_t n = static_cast<std::size_t>(std::min(kWindow, entities_ - first));
      w.buffer.resize(n * c);
      file_->read_at(w.buffer.data(), w.buffer.size() * sizeof(double), w.view->offset + first * c * sizeof(double));
    }
    const double* a = &w.buffer[static_cast<std::size_t>(v - first) * c];
    if (w.to_symmetric) {
      symmetric_components(a, out);
      out += 6;
    } else {
      out = std::copy(a, a + c, out);
    }
  }
}

}  // namespace topotet::ooc
