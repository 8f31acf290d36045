// Reading and writing mesh files. See vtk_io.hpp for the contract; the notes here say why the
// code does what it does.

#include "rgbmesh/vtk_io.hpp"

#include <fcntl.h>
#include <unistd.h>
#include <vtkAlgorithm.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkDataArray.h>
#include <vtkDataSet.h>
#include <vtkDoubleArray.h>
#include <vtkErrorCode.h>
#include <vtkIdTypeArray.h>
#include <vtkLogger.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkOutputWindow.h>
#include <vtkPLYWriter.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSTLReader.h>
#include <vtkSTLWriter.h>
#include <vtkSmartPointer.h>
#include <vtkTypeInt32Array.h>
#include <vtkTypeInt64Array.h>
#include <vtkUnsignedCharArray.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLPolyDataReader.h>
#include <vtkXMLPolyDataWriter.h>
#include <vtkXMLUnstructuredGridReader.h>
#include <vtkXMLUnstructuredGridWriter.h>
#include <vtkXMLWriter.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <mutex>
#include <sstream>
#include <string_view>
#include <unordered_map>

#include "parsers.hpp"

namespace rgbmesh {
namespace {

namespace fs = std::filesystem;

constexpr const char* input_extensions[] = {".obj", ".off", ".ply", ".stl", ".vtk", ".vtp", ".vtu"};
constexpr const char* point_cloud_extensions[] = {".obj", ".off", ".ply", ".pwn", ".stl",
                                                  ".vtk", ".vtp", ".vtu", ".xyz"};
constexpr const char* output_extensions[] = {".obj", ".off", ".ply", ".stl", ".vtp", ".vtu"};

std::string joined(const char* const* begin, const char* const* end) {
  std::string text;
  for (auto it = begin; it != end; ++it) text += (it == begin ? "" : ", ") + std::string(*it);
  return text;
}

std::string lowercase_extension(const fs::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

bool host_is_big_endian() {
  const std::uint16_t one = 1;
  unsigned char first;
  std::memcpy(&first, &one, 1);
  return first == 0;
}

// Shortest text that reads back as the same double.
std::string shortest(double x) {
  char buf[32];
  const auto result = std::to_chars(buf, buf + sizeof buf, x);
  return std::string(buf, result.ptr);
}

// ---------------------------------------------------------------------------------------------
// VTK's messages

// Keeps VTK's error texts instead of printing them.
class MessageCollector : public vtkOutputWindow {
 public:
  static MessageCollector* New();
  vtkTypeMacro(MessageCollector, vtkOutputWindow)

      // vtkOutputWindow routes every message type through DisplayText.
      void DisplayText(const char* text) override {
    if (text != nullptr && this->GetCurrentMessageType() == MESSAGE_TYPE_ERROR) errors.emplace_back(text);
  }

  std::vector<std::string> errors;
};
vtkStandardNewMacro(MessageCollector)

    // While alive, VTK prints nothing: its output window is replaced by a collector, and its logger
    // (which writes errors to stderr on its own, before the output window sees them) is silenced.
    // Both are process-wide, so VTK work in this file is serialized.
    class CapturedVtkMessages {
 public:
  CapturedVtkMessages() : lock_(vtk_mutex()), previous_window_(vtkOutputWindow::GetInstance()) {
    // SetInstance deletes the window it replaces; the extra reference keeps it for restoring.
    previous_window_->Register(nullptr);
    vtkOutputWindow::SetInstance(collector_);
    // vtkLogger has no getter for the stderr level; the cutoff equals it unless a log file or
    // callback asks for more.
    previous_verbosity_ = vtkLogger::GetCurrentVerbosityCutoff();
    vtkLogger::SetStderrVerbosity(vtkLogger::VERBOSITY_OFF);
  }
  ~CapturedVtkMessages() {
    vtkLogger::SetStderrVerbosity(previous_verbosity_);
    vtkOutputWindow::SetInstance(previous_window_);
    previous_window_->UnRegister(nullptr);
  }
  CapturedVtkMessages(const CapturedVtkMessages&) = delete;
  CapturedVtkMessages& operator=(const CapturedVtkMessages&) = delete;

  // The first error that says something, as one printable line. VTK's texts read
  // "ERROR: In <source>, line <n>\n<class> (0x...): <message>\n\n"; the location and the object
  // address mean nothing to a user. The pipeline's "Algorithm ... returned failure for request"
  // only repeats that the reader failed, so it is used only when there is nothing else.
  std::string first_error() const {
    std::string fallback;
    for (const std::string& text : collector_->errors) {
      const std::string message = message_of(text);
      if (message.empty()) continue;
      if (message.rfind("Algorithm ", 0) != 0) return message;
      if (fallback.empty()) fallback = "the VTK reader failed without saying why";
    }
    return fallback;
  }

 private:
  static std::mutex& vtk_mutex() {
    static std::mutex mutex;
    return mutex;
  }

  std::lock_guard<std::mutex> lock_;
  vtkOutputWindow* previous_window_;
  vtkNew<MessageCollector> collector_;
  vtkLogger::Verbosity previous_verbosity_ = vtkLogger::VERBOSITY_OFF;

  static std::string message_of(const std::string& text) {
    std::istringstream lines(text);
    std::string line;
    while (std::getline(lines, line)) {
      if (line.rfind("ERROR: In ", 0) == 0) continue;
      const auto address = line.find("(0x");
      const auto colon = line.find("): ");
      if (address != std::string::npos && colon != std::string::npos && address < colon)
        line.erase(0, colon + 3);
      for (char& c : line)
        if (!std::isprint(static_cast<unsigned char>(c))) c = '?';
      while (!line.empty() && line.back() == ' ') line.pop_back();
      constexpr std::size_t longest = 200;
      if (line.size() > longest) line = line.substr(0, longest) + "...";
      if (!line.empty()) return line;
    }
    return "";
  }
};

// Runs a reader; any VTK error or error code is an InputError naming the file.
void run_reader(vtkAlgorithm& reader, const fs::path& path) {
  CapturedVtkMessages messages;
  try {
    reader.Update();
  } catch (const std::bad_alloc&) {
    // VTK allocates what the file announces; a corrupt count asks for more than there is.
    throw InputError(path.string() + ": cannot read: the file announces more data than fits in memory");
  }
  std::string error = messages.first_error();
  if (error.empty() && reader.GetErrorCode() != vtkErrorCode::NoError)
    error = vtkErrorCode::GetStringFromErrorCode(reader.GetErrorCode());
  if (!error.empty()) throw InputError(path.string() + ": cannot read: " + error);
}

// ---------------------------------------------------------------------------------------------
// From VTK data sets to the soup

// The cells of a vtkCellArray as id lists. The XML readers do not validate what they read, so the
// offsets are checked before they are used to index the connectivity.
template <class IdArray>
detail::CellList cells_of(IdArray* offsets, IdArray* connectivity, const fs::path& path) {
  detail::CellList cells;
  const vtkIdType n_offsets = offsets != nullptr ? offsets->GetNumberOfValues() : 0;
  if (n_offsets <= 1) return cells;
  const vtkIdType n_ids = connectivity != nullptr ? connectivity->GetNumberOfValues() : 0;
  const auto* offset = offsets->GetPointer(0);
  const auto* ids = n_ids > 0 ? connectivity->GetPointer(0) : nullptr;
  if (offset[0] != 0)
    throw InputError(path.string() + ": cannot read: corrupt cell offsets (the first is not 0)");
  cells.reserve(static_cast<std::size_t>(n_offsets - 1));
  for (vtkIdType c = 0; c + 1 < n_offsets; ++c) {
    if (offset[c + 1] < offset[c] || offset[c + 1] > n_ids)
      throw InputError(path.string() + ": cannot read: corrupt cell offsets at cell " + std::to_string(c));
    cells.emplace_back(ids + offset[c], ids + offset[c + 1]);
  }
  return cells;
}

detail::CellList cells_of(vtkCellArray* cells, const fs::path& path) {
  if (cells == nullptr) return {};
  if (cells->IsStorage64Bit())
    return cells_of(cells->GetOffsetsArray64(), cells->GetConnectivityArray64(), path);
  return cells_of(cells->GetOffsetsArray32(), cells->GetConnectivityArray32(), path);
}

void append_points(vtkPoints* points, PolygonSoup& soup) {
  if (points == nullptr) return;
  const vtkIdType n = points->GetNumberOfPoints();
  soup.points.reserve(static_cast<std::size_t>(n));
  for (vtkIdType i = 0; i < n; ++i) {
    double p[3];
    points->GetPoint(i, p);
    soup.points.emplace_back(p[0], p[1], p[2]);
  }
}

// The data set's point normals, when asked for and present with one 3-vector per point.
void append_normals(vtkDataSet& data, const PolygonSoup& soup, const detail::ReadOptions& options) {
  vtkDataArray* normals = data.GetPointData() != nullptr ? data.GetPointData()->GetNormals() : nullptr;
  if (options.normals == nullptr || normals == nullptr || normals->GetNumberOfComponents() != 3 ||
      normals->GetNumberOfTuples() != static_cast<vtkIdType>(soup.points.size()))
    return;
  for (vtkIdType i = 0; i < normals->GetNumberOfTuples(); ++i) {
    double n[3];
    normals->GetTuple(i, n);
    options.normals->emplace_back(n[0], n[1], n[2]);
  }
}

PolygonSoup soup_of(vtkPolyData& data, const fs::path& path, const detail::ReadOptions& options) {
  PolygonSoup soup;
  append_points(data.GetPoints(), soup);
  detail::append_poly_data_cells(cells_of(data.GetVerts(), path), cells_of(data.GetLines(), path),
                                 cells_of(data.GetPolys(), path), cells_of(data.GetStrips(), path),
                                 path.string(), soup, options);
  append_normals(data, soup, options);
  return soup;
}

PolygonSoup soup_of(vtkUnstructuredGrid& grid, const fs::path& path, const detail::ReadOptions& options) {
  PolygonSoup soup;
  append_points(grid.GetPoints(), soup);
  const detail::CellList cells = cells_of(grid.GetCells(), path);
  std::vector<int> types;
  if (vtkUnsignedCharArray* type_array = grid.GetCellTypesArray())
    for (vtkIdType c = 0; c < type_array->GetNumberOfValues(); ++c) types.push_back(type_array->GetValue(c));
  if (types.size() != cells.size())
    throw InputError(path.string() + ": cannot read: " + std::to_string(cells.size()) + " cells but " +
                     std::to_string(types.size()) + " cell types");
  detail::append_grid_cells(cells, types, path.string(), soup, options);
  append_normals(grid, soup, options);
  return soup;
}

// STL stores every triangle's corners separately: exactly equal points are one vertex.
// Non-finite points are never merged (prepare_triangle_mesh reports them).
void merge_equal_points(PolygonSoup& soup) {
  struct Hash {
    std::size_t operator()(const Vec3& p) const {
      std::size_t h = 0;
      for (const double c : {p.x, p.y, p.z}) {
        std::uint64_t bits;
        const double normalized = c + 0.0;  // -0 and +0 are equal and must hash alike
        std::memcpy(&bits, &normalized, sizeof bits);
        h = h * 0x9E3779B97F4A7C15ull + (bits ^ (bits >> 29));
      }
      return h;
    }
  };
  std::unordered_map<Vec3, std::int64_t, Hash> index_of;
  index_of.reserve(soup.points.size());
  std::vector<std::int64_t> new_index(soup.points.size());
  std::vector<Vec3> merged;
  for (std::size_t i = 0; i < soup.points.size(); ++i) {
    const Vec3& p = soup.points[i];
    const auto next = static_cast<std::int64_t>(merged.size());
    if (!is_finite(p)) {
      new_index[i] = next;
      merged.push_back(p);
      continue;
    }
    const auto [it, inserted] = index_of.try_emplace(p, next);
    if (inserted) merged.push_back(p);
    new_index[i] = it->second;
  }
  const auto n = static_cast<std::int64_t>(new_index.size());
  for (auto& face : soup.faces)
    for (auto& v : face)
      if (v >= 0 && v < n) v = new_index[v];
  soup.points = std::move(merged);
}

// vtkSTLReader 9.1 reads a truncated binary STL without complaint, returning the triangles that
// are complete. A binary file must be exactly as long as its triangle count says. (ASCII files
// start with "solid" and hold only text; VTK reports their truncation itself.)
void check_binary_stl_length(const fs::path& path) {
  constexpr std::size_t header_bytes = 84, triangle_bytes = 50;
  std::ifstream in(path, std::ios::binary);
  std::string start(1024, '\0');
  in.read(start.data(), static_cast<std::streamsize>(start.size()));
  start.resize(static_cast<std::size_t>(in.gcount()));
  const bool text = std::all_of(start.begin(), start.end(), [](char c) {
    const auto u = static_cast<unsigned char>(c);
    return u >= 32 || c == '\n' || c == '\r' || c == '\t' || c == '\f' || c == '\v';
  });
  const auto word = start.find_first_not_of(" \t\r\n");
  if (text && word != std::string::npos && start.compare(word, 5, "solid") == 0) return;
  const std::uintmax_t size = fs::file_size(path);
  if (size < header_bytes)
    throw InputError(path.string() +
                     ": cannot read: a binary STL file needs an 84-byte header, the file has " +
                     std::to_string(size) + " bytes");
  std::uint32_t count = 0;  // little-endian by the format
  for (int i = 3; i >= 0; --i) count = count << 8 | static_cast<unsigned char>(start[80 + i]);
  const std::uintmax_t expected = header_bytes + triangle_bytes * static_cast<std::uintmax_t>(count);
  if (size < expected)
    throw InputError(path.string() + ": cannot read: the binary STL header announces " +
                     std::to_string(count) + " triangles (" + std::to_string(expected) +
                     " bytes), the file has " + std::to_string(size) + " bytes: it is truncated");
}

std::string file_contents(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string() + ": cannot open the file: " + std::strerror(errno));
  std::ostringstream contents;
  contents << in.rdbuf();
  if (in.bad()) throw InputError(path.string() + ": cannot read: " + std::strerror(errno));
  return contents.str();
}

// The value of attribute `name` in `text` ("" if absent).
std::string_view attribute(std::string_view text, std::string_view name) {
  const std::string key = " " + std::string(name) + "=\"";
  const auto at = text.find(key);
  if (at == std::string_view::npos) return {};
  const auto begin = at + key.size(), end = text.find('"', begin);
  return end == std::string_view::npos ? std::string_view() : text.substr(begin, end - begin);
}

// VTK's XML readers allocate what a file announces before reading the data: a damaged digit in
// the header's counts, or in the size header of a compressed array, made them take gigabytes
// (or throw bad_alloc) for a 3 kB file. Both are checked against the file here. Compressed data
// cannot expand by more than zlib's limit (about 1032 to 1).
void check_xml_sizes(const fs::path& path, std::string_view data) {
  constexpr std::uintmax_t expansion = 1032, slack = 1024;
  const auto damaged = [&](const std::string& what) {
    return InputError(path.string() + ": cannot read: " + what + ", more than the file can hold");
  };
  const std::size_t appended = data.find("<AppendedData");
  const std::string_view header = data.substr(0, appended);
  const std::uintmax_t limit = expansion * data.size() + slack;
  constexpr std::string_view count_attribute = " NumberOf";
  for (auto at = header.find(count_attribute); at != std::string_view::npos;
       at = header.find(count_attribute, at + 1)) {
    const auto quote = header.find('"', at);
    if (quote == std::string_view::npos) break;
    std::uintmax_t count = 0;
    const auto result = std::from_chars(header.data() + quote + 1, header.data() + header.size(), count);
    if (result.ec == std::errc::result_out_of_range || count > limit)
      throw damaged("the header announces " + std::string(header.substr(at + 1, quote - at)) + "...");
  }

  // Appended raw data starts after a '_'. Each array begins with its size header: its byte count
  // or, when compressed, [blocks, block size, last block size, compressed size of each block].
  const std::size_t underscore = appended == std::string_view::npos ? appended : data.find('_', appended);
  if (underscore == std::string_view::npos ||
      attribute(data.substr(appended, underscore - appended), "encoding") != "raw")
    return;
  const std::size_t start = underscore + 1;
  const std::size_t word_size = attribute(header, "header_type") == "UInt64" ? 8 : 4;
  const bool swap = (attribute(header, "byte_order") == "BigEndian") != host_is_big_endian();
  const bool compressed = !attribute(header, "compressor").empty();
  const auto word = [&](std::size_t at, std::uintmax_t& value) {
    if (at > data.size() || data.size() - at < word_size) return false;
    unsigned char bytes[8] = {};
    std::memcpy(bytes, data.data() + at, word_size);
    if (swap) std::reverse(bytes, bytes + word_size);
    value = 0;
    for (std::size_t i = word_size; i-- > 0;) value = value << 8 | bytes[i];
    return true;
  };
  constexpr std::string_view offset_attribute = " offset=\"";
  for (auto at = header.find(offset_attribute); at != std::string_view::npos;
       at = header.find(offset_attribute, at + 1)) {
    std::uintmax_t offset = 0;
    std::from_chars(header.data() + at + offset_attribute.size(), header.data() + header.size(), offset);
    const std::string where = "the size header of the array at offset " + std::to_string(offset);
    if (offset > data.size() - start) throw damaged("an array offset of " + std::to_string(offset));
    const std::size_t array = start + static_cast<std::size_t>(offset);
    std::uintmax_t first = 0;  // the byte count, or (compressed) the number of blocks
    if (!word(array, first)) throw damaged(where);
    const std::uintmax_t available = data.size() - array - word_size;
    if (!compressed) {
      if (first > available) throw damaged(where + " announces " + std::to_string(first) + " bytes");
      continue;
    }
    const std::uintmax_t blocks = first;
    std::uintmax_t block_size = 0, last_size = 0;
    if (blocks > available / word_size || !word(array + word_size, block_size) ||
        !word(array + 2 * word_size, last_size))
      throw damaged(where + " announces " + std::to_string(blocks) + " blocks");
    std::uintmax_t total = 0;
    for (std::uintmax_t b = 0; b < blocks; ++b) {
      std::uintmax_t size = 0;
      if (!word(array + (3 + b) * word_size, size) || size > available) throw damaged(where);
      total += size;
    }
    // The block size is nominal (32 kB from VTK's writers); the last block may be partial.
    const std::uintmax_t full_blocks = last_size == 0 ? blocks : blocks - (blocks > 0 ? 1 : 0);
    const bool sizes_fit = block_size <= limit && last_size <= block_size &&
                           (full_blocks == 0 || block_size <= limit / full_blocks) &&
                           full_blocks * block_size + last_size <= expansion * total + slack;
    if (total > available || !sizes_fit)
      throw damaged(where + " announces " + std::to_string(blocks) + " blocks of " +
                    std::to_string(block_size) + " bytes");
  }
}

PolygonSoup read_with_vtk(const fs::path& path, const std::string& ext, const detail::ReadOptions& options) {
  if (ext == ".stl") {
    check_binary_stl_length(path);
    vtkNew<vtkSTLReader> reader;
    reader->SetFileName(path.c_str());
    // VTK's merging uses a point locator, which is not safe with non-finite coordinates; exact
    // duplicates are merged below instead.
    reader->SetMerging(false);
    run_reader(*reader, path);
    PolygonSoup soup = soup_of(*reader->GetOutput(), path, options);
    merge_equal_points(soup);
    return soup;
  }
  check_xml_sizes(path, file_contents(path));
  if (ext == ".vtp") {
    vtkNew<vtkXMLPolyDataReader> reader;
    reader->SetFileName(path.c_str());
    run_reader(*reader, path);
    return soup_of(*reader->GetOutput(), path, options);
  }
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  reader->SetFileName(path.c_str());
  run_reader(*reader, path);
  return soup_of(*reader->GetOutput(), path, options);
}

// The checks and the dispatch by extension shared by mesh and point-cloud reading.
template <std::size_t N>
PolygonSoup read_soup(const fs::path& path, const char* const (&extensions)[N], const char* kind,
                      const detail::ReadOptions& options, std::vector<Vec3>& xyz_normals) {
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (!fs::exists(status)) throw InputError(path.string() + ": file does not exist");
  if (fs::is_directory(status)) throw InputError(path.string() + ": is a directory, not a mesh file");
  const std::string ext = lowercase_extension(path);
  if (std::find(std::begin(extensions), std::end(extensions), ext) == std::end(extensions))
    throw InputError(path.string() + ": unknown " + kind + " format '" + ext +
                     "' (supported: " + joined(std::begin(extensions), std::end(extensions)) + ")");
  // VTK's readers report an unreadable file with a message that does not say why.
  if (!std::ifstream(path, std::ios::binary))
    throw InputError(path.string() + ": cannot open the file: " + std::strerror(errno));
  if (ext == ".stl" || ext == ".vtp" || ext == ".vtu") return read_with_vtk(path, ext, options);
  const std::string contents = file_contents(path);
  if (ext == ".off") return detail::parse_off(contents, path.string());
  if (ext == ".obj") return detail::parse_obj(contents, path.string(), options);
  if (ext == ".ply") return detail::parse_ply(contents, path.string(), options);
  if (ext == ".xyz" || ext == ".pwn") return detail::parse_xyz(contents, path.string(), xyz_normals);
  return detail::parse_legacy_vtk(contents, path.string(), options);
}

// ---------------------------------------------------------------------------------------------
// Writing

// A hidden sibling with the same extension (writers pick formats by it), unique per process and
// call so that concurrent writes do not collide.
fs::path temporary_path_for(const fs::path& target) {
  static std::atomic<unsigned> counter{0};
  const std::string name = "." + target.stem().string() + ".tmp-" + std::to_string(::getpid()) + "-" +
                           std::to_string(counter++) + target.extension().string();
  return target.parent_path() / name;
}

// Without this the rename can reach the disk before the data, and a crash leaves an empty
// target.
void flush_to_disk(const fs::path& file) {
  const int fd = ::open(file.c_str(), O_RDONLY);
  if (fd < 0)
    throw std::runtime_error(std::string("cannot reopen the written file: ") + std::strerror(errno));
  const int synced = ::fsync(fd);
  const int sync_errno = errno;
  ::close(fd);
  if (synced != 0)
    throw std::runtime_error(std::string("cannot flush to disk: ") + std::strerror(sync_errno));
}

// Runs write(temp) and renames the temporary onto the target; on any failure the temporary is
// removed, the target untouched, and the error re-thrown as a runtime_error naming the target.
template <class Write>
void replace_atomically(const fs::path& target, Write&& write) {
  const fs::path temp = temporary_path_for(target);
  try {
    write(temp);
    if (!fs::is_regular_file(temp)) throw std::runtime_error("the writer created no file");
    flush_to_disk(temp);
    std::error_code ec;
    fs::rename(temp, target, ec);
    if (ec) throw std::runtime_error("cannot rename the temporary file onto it: " + ec.message());
  } catch (const std::exception& e) {
    std::error_code ignored;
    fs::remove(temp, ignored);
    throw std::runtime_error(target.string() + ": cannot write: " + e.what());
  }
}

// A new file written through a buffer, with every failure (full disk, size limit) reported.
class CheckedFile {
 public:
  explicit CheckedFile(const fs::path& file) : out_(file, std::ios::binary) {
    if (!out_) throw std::runtime_error(std::string("cannot create the file: ") + std::strerror(errno));
  }

  void append(std::string_view text) {
    buffer_ += text;
    if (buffer_.size() >= (1u << 20)) flush();
  }

  void close() {
    flush();
    out_.close();
    if (!out_) throw std::runtime_error(std::string("write failed: ") + std::strerror(errno));
  }

 private:
  void flush() {
    out_.write(buffer_.data(), static_cast<std::streamsize>(buffer_.size()));
    buffer_.clear();
    if (!out_) throw std::runtime_error(std::string("write failed: ") + std::strerror(errno));
  }

  std::ofstream out_;
  std::string buffer_;
};

void write_bytes(const fs::path& file, std::string_view contents) {
  CheckedFile out(file);
  out.append(contents);
  out.close();
}

// OFF and OBJ are written here: shortest round-trip numbers, and (unlike vtkOBJWriter, which
// ignores failed writes) every I/O error reported.
void write_off(const fs::path& file, const MeshSnapshot& mesh) {
  CheckedFile out(file);
  out.append("OFF\n" + std::to_string(mesh.points.size()) + " " + std::to_string(mesh.triangles.size()) +
             " 0\n");
  for (const Vec3& p : mesh.points)
    out.append(shortest(p.x) + " " + shortest(p.y) + " " + shortest(p.z) + "\n");
  for (const auto& t : mesh.triangles)
    out.append("3 " + std::to_string(t[0]) + " " + std::to_string(t[1]) + " " + std::to_string(t[2]) + "\n");
  out.close();
}

void write_obj(const fs::path& file, const MeshSnapshot& mesh) {
  CheckedFile out(file);
  out.append("# written by rgbmesh\n");
  for (const Vec3& p : mesh.points)
    out.append("v " + shortest(p.x) + " " + shortest(p.y) + " " + shortest(p.z) + "\n");
  for (const auto& t : mesh.triangles)  // OBJ counts vertices from 1
    out.append("f " + std::to_string(t[0] + 1) + " " + std::to_string(t[1] + 1) + " " +
               std::to_string(t[2] + 1) + "\n");
  out.close();
}

// Programming errors in the snapshot are caught before anything is written.
void check_snapshot(const MeshSnapshot& mesh, const fs::path& path) {
  const auto fail = [&](const std::string& what) {
    throw std::invalid_argument(path.string() + ": inconsistent mesh snapshot: " + what);
  };
  const std::size_t n_points = mesh.points.size(), n_cells = mesh.triangles.size();
  for (std::size_t t = 0; t < n_cells; ++t)
    for (const std::int32_t v : mesh.triangles[t])
      if (v < 0 || static_cast<std::size_t>(v) >= n_points)
        fail("triangle " + std::to_string(t) + " references point " + std::to_string(v) + " of " +
             std::to_string(n_points));
  if (!mesh.vertex_level.empty() && mesh.vertex_level.size() != n_points)
    fail("vertex_level has the wrong size");
  if (!mesh.triangle_level.empty() && mesh.triangle_level.size() != n_cells)
    fail("triangle_level has the wrong size");
  if (!mesh.triangle_color.empty() && mesh.triangle_color.size() != n_cells)
    fail("triangle_color has the wrong size");
  const auto check_arrays = [&](const std::vector<NamedArray>& arrays, std::size_t n) {
    for (const NamedArray& a : arrays)
      if (a.name.empty() || a.components < 1 || a.values.size() != n * static_cast<std::size_t>(a.components))
        fail("array '" + a.name + "' needs a name and " + std::to_string(a.components) + " x " +
             std::to_string(n) + " values");
  };
  check_arrays(mesh.point_data, n_points);
  check_arrays(mesh.cell_data, n_cells);
}

vtkSmartPointer<vtkPoints> vtk_points(const MeshSnapshot& mesh) {
  // Double precision, so that VTP/VTU round trips are exact.
  vtkNew<vtkDoubleArray> coordinates;
  coordinates->SetNumberOfComponents(3);
  coordinates->SetNumberOfTuples(static_cast<vtkIdType>(mesh.points.size()));
  double* out = coordinates->GetPointer(0);
  for (const Vec3& p : mesh.points) {
    *out++ = p.x;
    *out++ = p.y;
    *out++ = p.z;
  }
  auto points = vtkSmartPointer<vtkPoints>::New();
  points->SetData(coordinates);
  return points;
}

vtkSmartPointer<vtkCellArray> vtk_triangles(const MeshSnapshot& mesh) {
  const auto n = static_cast<vtkIdType>(mesh.triangles.size());
  vtkNew<vtkIdTypeArray> offsets, connectivity;
  offsets->SetNumberOfValues(n + 1);
  connectivity->SetNumberOfValues(3 * n);
  for (vtkIdType t = 0; t <= n; ++t) offsets->SetValue(t, 3 * t);
  for (vtkIdType t = 0; t < n; ++t)
    for (int k = 0; k < 3; ++k) connectivity->SetValue(3 * t + k, mesh.triangles[t][k]);
  auto cells = vtkSmartPointer<vtkCellArray>::New();
  cells->SetData(offsets, connectivity);
  return cells;
}

template <class T>
vtkSmartPointer<vtkUnsignedCharArray> uint8_array(const char* name, const std::vector<T>& values) {
  auto array = vtkSmartPointer<vtkUnsignedCharArray>::New();
  array->SetName(name);
  array->SetNumberOfValues(static_cast<vtkIdType>(values.size()));
  for (std::size_t i = 0; i < values.size(); ++i)
    array->SetValue(static_cast<vtkIdType>(i), static_cast<unsigned char>(values[i]));
  return array;
}

vtkSmartPointer<vtkDoubleArray> float64_array(const NamedArray& named) {
  auto array = vtkSmartPointer<vtkDoubleArray>::New();
  array->SetName(named.name.c_str());
  array->SetNumberOfComponents(named.components);
  array->SetNumberOfTuples(static_cast<vtkIdType>(named.values.size() / named.components));
  std::copy(named.values.begin(), named.values.end(), array->GetPointer(0));
  return array;
}

void add_arrays(vtkDataSet& data, const MeshSnapshot& mesh) {
  if (!mesh.vertex_level.empty()) data.GetPointData()->AddArray(uint8_array("level", mesh.vertex_level));
  if (!mesh.triangle_level.empty()) data.GetCellData()->AddArray(uint8_array("level", mesh.triangle_level));
  if (!mesh.triangle_color.empty()) data.GetCellData()->AddArray(uint8_array("color", mesh.triangle_color));
  for (const NamedArray& a : mesh.point_data) data.GetPointData()->AddArray(float64_array(a));
  for (const NamedArray& a : mesh.cell_data) data.GetCellData()->AddArray(float64_array(a));
}

vtkSmartPointer<vtkPolyData> vtk_poly_data(const MeshSnapshot& mesh) {
  auto data = vtkSmartPointer<vtkPolyData>::New();
  data->SetPoints(vtk_points(mesh));
  data->SetPolys(vtk_triangles(mesh));
  return data;
}

// Runs a writer whose file name is set (VTK's XML writers are no vtkWriter, hence the template);
// any VTK error or error code is a failure.
template <class Writer>
void run_writer(Writer& writer) {
  CapturedVtkMessages messages;
  const int written = writer.Write();
  std::string error = messages.first_error();
  if (error.empty() && writer.GetErrorCode() != vtkErrorCode::NoError)
    error = vtkErrorCode::GetStringFromErrorCode(writer.GetErrorCode());
  if (error.empty() && written != 1) error = "the VTK writer failed";
  if (!error.empty()) throw std::runtime_error(error);
}

// Appended raw binary, zlib-compressed: the smallest files ParaView reads fastest.
void configure_xml(vtkXMLWriter& writer) {
  writer.SetDataModeToAppended();
  writer.EncodeAppendedDataOff();
  writer.SetCompressorTypeToZLib();
}

// vtkPLYWriter ignores failed writes (a full disk leaves a short file and no error), so the
// file is checked: after its header, a binary PLY of ours holds exactly 12 bytes per point
// (float x, y, z) and 13 per triangle (uchar 3, int a, b, c).
void check_ply_length(const fs::path& file, const MeshSnapshot& mesh) {
  std::ifstream in(file, std::ios::binary);
  std::string header;
  for (std::string line; std::getline(in, line) && line != "end_header";) header += line + "\n";
  const std::uintmax_t expected = header.size() + std::string("end_header\n").size() +
                                  12 * mesh.points.size() + 13 * mesh.triangles.size();
  std::error_code ec;
  const std::uintmax_t size = fs::file_size(file, ec);
  if (!in || ec || size != expected)
    throw std::runtime_error("the PLY writer left an incomplete file (" + std::to_string(ec ? 0 : size) +
                             " of " + std::to_string(expected) + " bytes)");
}

void write_with_vtk(const fs::path& file, const std::string& ext, const MeshSnapshot& mesh) {
  if (ext == ".vtu") {
    vtkNew<vtkUnstructuredGrid> grid;
    grid->SetPoints(vtk_points(mesh));
    grid->SetCells(VTK_TRIANGLE, vtk_triangles(mesh));
    add_arrays(*grid, mesh);
    vtkNew<vtkXMLUnstructuredGridWriter> writer;
    configure_xml(*writer);
    writer->SetInputData(grid);
    writer->SetFileName(file.c_str());
    run_writer(*writer);
    return;
  }
  const vtkSmartPointer<vtkPolyData> data = vtk_poly_data(mesh);
  if (ext == ".vtp") {
    add_arrays(*data, mesh);
    vtkNew<vtkXMLPolyDataWriter> writer;
    configure_xml(*writer);
    writer->SetInputData(data);
    writer->SetFileName(file.c_str());
    run_writer(*writer);
  } else if (ext == ".ply") {
    vtkNew<vtkPLYWriter> writer;
    writer->SetFileTypeToBinary();
    writer->SetInputData(data);
    writer->SetFileName(file.c_str());
    run_writer(*writer);
    check_ply_length(file, mesh);
  } else {
    vtkNew<vtkSTLWriter> writer;
    writer->SetFileTypeToBinary();
    writer->SetInputData(data);
    writer->SetFileName(file.c_str());
    run_writer(*writer);
  }
}

std::string xml_attribute(const std::string& value) {
  std::string escaped;
  for (const char c : value) {
    switch (c) {
      case '&':
        escaped += "&amp;";
        break;
      case '<':
        escaped += "&lt;";
        break;
      case '>':
        escaped += "&gt;";
        break;
      case '"':
        escaped += "&quot;";
        break;
      case '\'':
        escaped += "&apos;";
        break;
      default:
        escaped += c;
    }
  }
  return escaped;
}

}  // namespace

MeshSnapshot snapshot_for_file(RgbMesh& mesh, const fs::path& path, bool limit_points) {
  const std::string ext = lowercase_extension(path);
  const bool xml = ext == ".vtp" || ext == ".vtu";
  if (limit_points || xml) mesh.compute_limits();
  return mesh.snapshot(limit_points ? RgbMesh::Points::limit : RgbMesh::Points::control, xml);
}

std::string supported_input_extensions() {
  return joined(std::begin(input_extensions), std::end(input_extensions));
}

std::string supported_output_extensions() {
  return joined(std::begin(output_extensions), std::end(output_extensions));
}

PolygonSoup read_polygon_soup(const fs::path& path) {
  std::vector<Vec3> unused;
  return read_soup(path, input_extensions, "mesh", {}, unused);
}

std::string supported_point_cloud_extensions() {
  return joined(std::begin(point_cloud_extensions), std::end(point_cloud_extensions));
}

PointCloud read_point_cloud(const fs::path& path) {
  PointCloud cloud;
  detail::ReadOptions options;
  options.skip_vertex_cells = true;
  options.normals = &cloud.normals;
  PolygonSoup soup = read_soup(path, point_cloud_extensions, "point-cloud", options, cloud.normals);
  cloud.points = std::move(soup.points);
  cloud.faces = std::move(soup.faces);
  if (cloud.points.empty()) throw InputError(path.string() + ": no points");
  for (std::size_t i = 0; i < cloud.points.size(); ++i)
    if (!is_finite(cloud.points[i]))
      throw InputError(path.string() + ": point " + std::to_string(i) + " is not finite");
  // Some tools write placeholder normals (all zero); a normal that gives no direction makes the
  // set unusable, since the users of normals need every point's.
  if (!cloud.normals.empty()) {
    std::size_t unusable = 0;
    for (const Vec3& n : cloud.normals) unusable += !is_finite(n) || norm(n) == 0;
    if (unusable > 0 || cloud.normals.size() != cloud.points.size()) {
      cloud.notes.push_back(path.string() + ": " + std::to_string(unusable) + " of " +
                            std::to_string(cloud.normals.size()) +
                            " normals are zero or not finite: the file's normals are ignored");
      cloud.normals.clear();
    }
  }
  return cloud;
}

TriangleMeshData read_mesh(const fs::path& path, const SoupOptions& options) {
  const PolygonSoup soup = read_polygon_soup(path);
  try {
    return prepare_triangle_mesh(soup, options);
  } catch (const InputError& e) {
    throw InputError(path.string() + ": " + e.what());
  }
}

void write_mesh(const fs::path& path, const MeshSnapshot& mesh) {
  const std::string ext = lowercase_extension(path);
  if (std::find(std::begin(output_extensions), std::end(output_extensions), ext) ==
      std::end(output_extensions))
    throw InputError(path.string() + ": unknown output format '" + ext +
                     "' (supported: " + supported_output_extensions() + ")");
  check_snapshot(mesh, path);
  replace_atomically(path, [&](const fs::path& temp) {
    if (ext == ".off")
      write_off(temp, mesh);
    else if (ext == ".obj")
      write_obj(temp, mesh);
    else
      write_with_vtk(temp, ext, mesh);
  });
}

void write_point_cloud(const fs::path& path, const std::vector<Vec3>& points,
                       const std::vector<NamedArray>& point_data) {
  if (lowercase_extension(path) != ".vtp")
    throw InputError(path.string() + ": point clouds are written as .vtp, not '" + lowercase_extension(path) +
                     "'");
  MeshSnapshot cloud;  // for the shared checks and conversions; it has no triangles
  cloud.points = points;
  cloud.point_data = point_data;
  check_snapshot(cloud, path);
  const auto n = static_cast<vtkIdType>(points.size());
  vtkNew<vtkIdTypeArray> offsets, connectivity;
  offsets->SetNumberOfValues(n + 1);
  connectivity->SetNumberOfValues(n);
  for (vtkIdType i = 0; i <= n; ++i) offsets->SetValue(i, i);
  for (vtkIdType i = 0; i < n; ++i) connectivity->SetValue(i, i);
  vtkNew<vtkCellArray> vertices;
  vertices->SetData(offsets, connectivity);
  vtkNew<vtkPolyData> data;
  data->SetPoints(vtk_points(cloud));
  data->SetVerts(vertices);
  add_arrays(*data, cloud);
  replace_atomically(path, [&](const fs::path& temp) {
    vtkNew<vtkXMLPolyDataWriter> writer;
    configure_xml(*writer);
    writer->SetInputData(data);
    writer->SetFileName(temp.c_str());
    run_writer(*writer);
  });
}

void write_text_atomically(const fs::path& path, const std::string& contents) {
  replace_atomically(path, [&](const fs::path& temp) { write_bytes(temp, contents); });
}

void write_pvd(const fs::path& pvd,
               const std::vector<std::pair<double, std::string>>& time_and_relative_file) {
  std::string xml =
      "<?xml version=\"1.0\"?>\n"
      "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
      "  <Collection>\n";
  for (const auto& [time, file] : time_and_relative_file) {
    if (!std::isfinite(time))
      throw std::invalid_argument(pvd.string() + ": time " + shortest(time) + " is not finite");
    xml += "    <DataSet timestep=\"" + shortest(time) + "\" group=\"\" part=\"0\" file=\"" +
           xml_attribute(file) + "\"/>\n";
  }
  xml +=
      "  </Collection>\n"
      "</VTKFile>\n";
  write_text_atomically(pvd, xml);
}

}  // namespace rgbmesh
