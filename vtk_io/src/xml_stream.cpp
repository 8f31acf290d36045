// The streaming VTK XML writer (xml_stream.hpp).
//
// Layout of the file (what vtkXMLWriter writes in appended raw mode, file version 1.0):
//
//   <VTKFile type="PolyData" version="1.0" byte_order="LittleEndian" header_type="UInt64"
//            compressor="vtkLZ4DataCompressor">
//     ... <DataArray ... format="appended" offset="N"/> for every array ...
//     <AppendedData encoding="raw">
//      _[array at offset 0][array at offset N]...
//     </AppendedData>
//   </VTKFile>
//
// An uncompressed array is [UInt64 byte count][values]; a compressed one is [UInt64 number of
// blocks][block size][size of the last block, 0 if full][compressed size of each block]
// [the compressed blocks]. Offsets and compressed sizes are known only once the data is
// written, so the XML header is written first with every offset padded to a fixed width, each
// array's block table is reserved before its blocks, and both are rewritten in place at the end
// (vtkXMLWriter does the same).

#include "xml_stream.hpp"

#include <fcntl.h>
#include <unistd.h>
#include <vtkDataCompressor.h>
#include <vtkLZ4DataCompressor.h>
#include <vtkSmartPointer.h>
#include <vtkZLibDataCompressor.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <exception>
#include <stdexcept>

#include "rgbmesh/detail/parallel_for.hpp"

namespace rgbmesh::detail {
namespace {

namespace fs = std::filesystem;

static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, "the files are written as LittleEndian");

// Uncompressed bytes per block: VTK's default (larger blocks made the files no smaller and the
// writes no faster). Each array's blocks hold whole tuples, so that a block is filled by one
// call of the array's fill function.
constexpr std::size_t kBlockBytes = 32768;
// Blocks compressed between two writes to the file: a few MB in memory.
constexpr std::size_t kBatchBlocks = 64;
// Width of the offsets in the XML header, so that it can be rewritten in place.
constexpr std::size_t kOffsetWidth = 20;

std::size_t type_size(XmlType type) {
  switch (type) {
    case XmlType::uint8:
      return 1;
    case XmlType::int32:
      return 4;
    case XmlType::int64:
    case XmlType::float64:
      return 8;
  }
  return 0;
}

// A file written at its end and patched in place, every failure (full disk, size limit)
// reported with the system's reason.
class PatchableFile {
 public:
  explicit PatchableFile(const fs::path& file) : fd_(::open(file.c_str(), O_WRONLY | O_TRUNC | O_CLOEXEC)) {
    if (fd_ < 0) fail("cannot open the file");
  }
  ~PatchableFile() {
    if (fd_ >= 0) ::close(fd_);
  }
  PatchableFile(const PatchableFile&) = delete;
  PatchableFile& operator=(const PatchableFile&) = delete;

  std::uint64_t size() const { return size_; }
  void append(const void* data, std::size_t bytes) {
    write_at(size_, data, bytes);
    size_ += bytes;
  }
  void append(const std::string& text) { append(text.data(), text.size()); }
  void write_at(std::uint64_t position, const void* data, std::size_t bytes) {
    const auto* p = static_cast<const char*>(data);
    while (bytes > 0) {
      const ssize_t written = ::pwrite(fd_, p, bytes, static_cast<off_t>(position));
      if (written < 0 && errno == EINTR) continue;
      if (written <= 0) fail("cannot write");
      p += written;
      position += static_cast<std::uint64_t>(written);
      bytes -= static_cast<std::size_t>(written);
    }
  }
  void close() {
    const int fd = fd_;
    fd_ = -1;
    if (::close(fd) != 0) fail("cannot close the file");
  }

 private:
  [[noreturn]] static void fail(const char* what) {
    throw std::runtime_error(std::string(what) + ": " + std::strerror(errno));
  }
  int fd_;
  std::uint64_t size_ = 0;
};

// One compressor per thread: VTK's compressors keep no state between blocks, but they are
// objects with settings, not documented as safe to share.
vtkSmartPointer<vtkDataCompressor> make_compressor(Compression compression) {
  switch (compression) {
    case Compression::lz4: {
      // Level 9: LZ4's own default acceleration (VTK's default level 5 made files 3% larger,
      // no faster).
      auto lz4 = vtkSmartPointer<vtkLZ4DataCompressor>::New();
      lz4->SetCompressionLevel(9);
      return lz4;
    }
    case Compression::zlib: {
      // Level 1: VTK's default 5 took 1.7 times as long for files of the same size (the
      // coordinates hardly compress).
      auto zlib = vtkSmartPointer<vtkZLibDataCompressor>::New();
      zlib->SetCompressionLevel(1);
      return zlib;
    }
    case Compression::none:
      break;
  }
  return nullptr;
}

class Writer {
 public:
  Writer(const fs::path& file, const XmlDataSet& data, Compression compression,
         const std::function<void(double)>& progress)
      : file_(file), data_(data), compression_(compression), progress_(progress) {
    threads_ = rgbmesh::detail::hardware_threads();
    for (std::size_t t = 0; t < threads_; ++t) {
      compressors_.push_back(make_compressor(compression));
      raw_.emplace_back(kBlockBytes);
    }
    collect_arrays();
  }

  void run() {
    const std::string placeholder = header(std::vector<std::uint64_t>(arrays_.size(), 0));
    file_.append(placeholder);
    file_.append("  <AppendedData encoding=\"raw\">\n   _");
    const std::uint64_t base = file_.size();
    std::vector<std::uint64_t> offsets;
    for (const XmlArray* array : arrays_) {
      offsets.push_back(file_.size() - base);
      write_array(*array);
    }
    file_.append("\n  </AppendedData>\n</VTKFile>\n");
    const std::string final_header = header(offsets);
    if (final_header.size() != placeholder.size())
      throw std::logic_error("the XML header changed length when its offsets were filled in");
    file_.write_at(0, final_header.data(), final_header.size());
    file_.close();
  }

 private:
  void collect_arrays() {
    const auto check = [](const XmlArray& a, std::size_t tuples, const char* where) {
      if (a.tuples != tuples || a.components < 1 || !a.fill || a.name.empty())
        throw std::invalid_argument(std::string(where) + " array '" + a.name + "' has " + std::to_string(a.tuples) +
                                    " tuples for " + std::to_string(tuples));
    };
    for (const XmlArray& a : data_.field_data) {
      check(a, a.tuples, "field data");
      arrays_.push_back(&a);
    }
    for (const XmlArray& a : data_.point_data) {
      check(a, data_.points, "point data");
      arrays_.push_back(&a);
    }
    for (const XmlArray& a : data_.cell_data) {
      check(a, data_.cells, "cell data");
      arrays_.push_back(&a);
    }
    check(data_.coordinates, data_.points, "the points'");
    if (data_.coordinates.components != 3 || data_.coordinates.type != XmlType::float64)
      throw std::invalid_argument("the points must be Float64 with 3 components");
    arrays_.push_back(&data_.coordinates);

    const bool quadratic = data_.kind == XmlDataSet::Kind::grid_quadratic_triangles;
    const std::size_t per_cell = data_.kind == XmlDataSet::Kind::poly_vertices ? 1 : quadratic ? 6 : 3;
    if (data_.connectivity.type != XmlType::int32 || data_.connectivity.components != 1)
      throw std::invalid_argument("the connectivity must be Int32 with 1 component");
    check(data_.connectivity, per_cell * data_.cells, "the cells'");
    // Offsets: where each cell ends in the connectivity (file versions before 2.0 leave out the
    // leading 0). Int32 where they fit, as vtkXMLWriter makes them for Int32 connectivity.
    const bool wide = per_cell * data_.cells > static_cast<std::size_t>(INT32_MAX);
    offsets_ = XmlArray{"offsets", wide ? XmlType::int64 : XmlType::int32, 1, data_.cells,
                        [per_cell, wide](std::size_t first, std::size_t count, void* out) {
                          for (std::size_t i = 0; i < count; ++i) {
                            const std::size_t end = per_cell * (first + i + 1);
                            if (wide)
                              static_cast<std::int64_t*>(out)[i] = static_cast<std::int64_t>(end);
                            else
                              static_cast<std::int32_t*>(out)[i] = static_cast<std::int32_t>(end);
                          }
                        }};
    const int type = quadratic ? 22 : 5;  // VTK_QUADRATIC_TRIANGLE, VTK_TRIANGLE
    types_ = XmlArray{"types", XmlType::uint8, 1, data_.cells, [type](std::size_t, std::size_t count, void* out) {
                        std::memset(out, type, count);
                      }};
    empty_ = XmlArray{"", XmlType::int64, 1, 0, [](std::size_t, std::size_t, void*) {}};
    if (grid()) {
      arrays_.insert(arrays_.end(), {&data_.connectivity, &offsets_, &types_});
    } else {
      // Verts, Lines, Strips, Polys: the cells in Verts or Polys, the others empty.
      const bool vertices = data_.kind == XmlDataSet::Kind::poly_vertices;
      for (int section = 0; section < 4; ++section) {
        const bool used = vertices ? section == 0 : section == 3;
        arrays_.push_back(used ? &data_.connectivity : &empty_);
        arrays_.push_back(used ? &offsets_ : &empty_);
      }
    }
    for (const XmlArray* a : arrays_) total_bytes_ += a->tuples * static_cast<std::size_t>(a->components) * type_size(a->type);
  }

  static std::string attribute(const std::string& value) { return xml_attribute(value); }
  bool grid() const {
    return data_.kind == XmlDataSet::Kind::grid_triangles || data_.kind == XmlDataSet::Kind::grid_quadratic_triangles;
  }

  std::string header(const std::vector<std::uint64_t>& offsets) const {
    std::size_t next = 0;
    const auto data_array = [&](const XmlArray& a, const std::string& name, bool tuples, const std::string& indent) {
      // Padded after the closing quote, as vtkXMLWriter does: the value itself has no spaces.
      std::string offset = std::to_string(offsets[next++]) + "\"";
      offset.resize(kOffsetWidth + 1, ' ');
      std::string line = indent + "<DataArray type=\"" + type_name(a.type) + "\" Name=\"" + attribute(name) + "\"";
      if (a.components != 1) line += " NumberOfComponents=\"" + std::to_string(a.components) + "\"";
      if (tuples) line += " NumberOfTuples=\"" + std::to_string(a.tuples) + "\"";
      return line + " format=\"appended\" offset=\"" + offset + "/>\n";
    };
    const std::string type = grid() ? "UnstructuredGrid" : "PolyData";
    std::string xml = "<VTKFile type=\"" + type + "\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\"";
    if (compression_ == Compression::lz4) xml += " compressor=\"vtkLZ4DataCompressor\"";
    if (compression_ == Compression::zlib) xml += " compressor=\"vtkZLibDataCompressor\"";
    xml += ">\n  <" + type + ">\n";
    if (!data_.field_data.empty()) {
      xml += "    <FieldData>\n";
      for (const XmlArray& a : data_.field_data) xml += data_array(a, a.name, true, "      ");
      xml += "    </FieldData>\n";
    }
    const std::string points = std::to_string(data_.points), cells = std::to_string(data_.cells);
    if (grid()) {
      xml += "    <Piece NumberOfPoints=\"" + points + "\" NumberOfCells=\"" + cells + "\">\n";
    } else {
      const bool vertices = data_.kind == XmlDataSet::Kind::poly_vertices;
      xml += "    <Piece NumberOfPoints=\"" + points + "\" NumberOfVerts=\"" + (vertices ? cells : "0") +
             "\" NumberOfLines=\"0\" NumberOfStrips=\"0\" NumberOfPolys=\"" + (vertices ? "0" : cells) + "\">\n";
    }
    xml += "      <PointData>\n";
    for (const XmlArray& a : data_.point_data) xml += data_array(a, a.name, false, "        ");
    xml += "      </PointData>\n      <CellData>\n";
    for (const XmlArray& a : data_.cell_data) xml += data_array(a, a.name, false, "        ");
    xml += "      </CellData>\n      <Points>\n";
    xml += data_array(data_.coordinates, "Points", false, "        ");
    xml += "      </Points>\n";
    const auto cell_section = [&](const std::string& section, bool with_types) {
      xml += "      <" + section + ">\n";
      xml += data_array(*arrays_[next], "connectivity", false, "        ");
      xml += data_array(*arrays_[next], "offsets", false, "        ");
      if (with_types) xml += data_array(*arrays_[next], "types", false, "        ");
      xml += "      </" + section + ">\n";
    };
    if (grid()) {
      cell_section("Cells", true);
    } else {
      for (const char* section : {"Verts", "Lines", "Strips", "Polys"}) cell_section(section, false);
    }
    xml += "    </Piece>\n  </" + type + ">\n";
    return xml;
  }

  void report(std::size_t bytes) {
    done_bytes_ += bytes;
    if (progress_ && total_bytes_ > 0) progress_(std::min(0.999, static_cast<double>(done_bytes_) / static_cast<double>(total_bytes_)));
  }

  void write_array(const XmlArray& a) {
    const std::size_t tuple_bytes = static_cast<std::size_t>(a.components) * type_size(a.type);
    const std::size_t bytes = a.tuples * tuple_bytes;
    const std::size_t block_tuples = std::max<std::size_t>(1, kBlockBytes / tuple_bytes);
    const std::size_t block_bytes = block_tuples * tuple_bytes;
    const std::size_t blocks = (a.tuples + block_tuples - 1) / block_tuples;
    for (std::vector<unsigned char>& raw : raw_) raw.resize(std::max(raw.size(), block_bytes));
    if (compression_ == Compression::none) {
      const std::uint64_t count = bytes;
      file_.append(&count, sizeof count);
    }
    // The block table, rewritten once the compressed sizes are known.
    std::vector<std::uint64_t> table;
    std::uint64_t table_position = file_.size();
    if (compression_ != Compression::none) {
      table.assign(3 + blocks, 0);
      table[0] = blocks;
      table[1] = block_bytes;
      table[2] = bytes % block_bytes;
      file_.append(table.data(), table.size() * sizeof(std::uint64_t));
    }
    // Every block's buffer at its largest, made here: the worker threads then allocate nothing,
    // and so get no malloc arenas of their own (with huge pages, 2 MB or more resident each).
    std::vector<std::vector<unsigned char>> out(kBatchBlocks);
    std::vector<std::size_t> out_size(kBatchBlocks);
    const std::size_t largest =
        compression_ == Compression::none ? block_bytes : static_cast<std::size_t>(compressors_[0]->GetMaximumCompressionSpace(block_bytes));
    for (std::vector<unsigned char>& buffer : out) buffer.reserve(largest);
    for (std::size_t first = 0; first < blocks; first += kBatchBlocks) {
      const std::size_t batch = std::min(kBatchBlocks, blocks - first);
      rgbmesh::detail::parallel_for(batch, 1, threads_, [&](std::size_t thread, std::size_t i) {
        const std::size_t block = first + i;
        const std::size_t tuple = block * block_tuples;
        const std::size_t count = std::min(block_tuples, a.tuples - tuple);
        const std::size_t size = count * tuple_bytes;
        if (compression_ == Compression::none) {
          out[i].resize(size);
          a.fill(tuple, count, out[i].data());
          out_size[i] = size;
          return;
        }
        std::vector<unsigned char>& raw = raw_[thread];
        a.fill(tuple, count, raw.data());
        vtkDataCompressor& compressor = *compressors_[thread];
        out[i].resize(compressor.GetMaximumCompressionSpace(size));
        out_size[i] = compressor.Compress(raw.data(), size, out[i].data(), out[i].size());
        if (out_size[i] == 0) throw std::runtime_error("the compressor failed on a block of '" + a.name + "'");
      });
      std::size_t batch_bytes = 0;
      for (std::size_t i = 0; i < batch; ++i) {
        file_.append(out[i].data(), out_size[i]);
        if (compression_ != Compression::none) table[3 + first + i] = out_size[i];
        batch_bytes += std::min(block_bytes, bytes - (first + i) * block_bytes);
      }
      report(batch_bytes);
    }
    if (compression_ != Compression::none)
      file_.write_at(table_position, table.data(), table.size() * sizeof(std::uint64_t));
  }

  PatchableFile file_;
  const XmlDataSet& data_;
  Compression compression_;
  const std::function<void(double)>& progress_;
  std::size_t threads_ = 1;
  std::vector<vtkSmartPointer<vtkDataCompressor>> compressors_;
  std::vector<std::vector<unsigned char>> raw_;  // one block per thread
  std::vector<const XmlArray*> arrays_;          // in the order of the header and the data
  XmlArray offsets_, types_, empty_;
  std::size_t total_bytes_ = 0, done_bytes_ = 0;
};

}  // namespace

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

void write_vtk_xml(const fs::path& file, const XmlDataSet& data, Compression compression,
                   const std::function<void(double)>& progress) {
  Writer(file, data, compression, progress).run();
}

XmlArray borrowed_array(std::string name, XmlType type, int components, std::size_t tuples, const void* values) {
  const std::size_t tuple_bytes = static_cast<std::size_t>(components) * type_size(type);
  const auto* bytes = static_cast<const unsigned char*>(values);
  return XmlArray{std::move(name), type, components, tuples,
                  [bytes, tuple_bytes](std::size_t first, std::size_t count, void* out) {
                    if (count > 0) std::memcpy(out, bytes + first * tuple_bytes, count * tuple_bytes);
                  }};
}

const char* type_name(XmlType type) {
  switch (type) {
    case XmlType::uint8:
      return "UInt8";
    case XmlType::int32:
      return "Int32";
    case XmlType::int64:
      return "Int64";
    case XmlType::float64:
      return "Float64";
  }
  return "?";
}

}  // namespace rgbmesh::detail
