#include "roar/track/npz.h"

#include "roar/config/text_file.h"

#include <zip.h>
#include <zlib.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>
#include <regex>

namespace roar::track {

namespace {

// Waypoint files hold thousands of points: a million rows of three is far beyond any circuit.
constexpr std::size_t kMaxNpyValues = std::size_t{1} << 22;
constexpr std::size_t kNpyHeaderRead = 4096;  // bytes read to find an array's size (numpy writes 128)

struct ZipCloser {
  void operator()(zip_t* z) const {
    if (z) zip_discard(z);
  }
};
struct FileCloser {
  void operator()(zip_file_t* f) const {
    if (f) zip_fclose(f);
  }
};

NpyArray parseNpy(const std::vector<std::uint8_t>& bytes, const std::string& where) {
  if (bytes.size() < 10 || std::memcmp(bytes.data(), "\x93NUMPY", 6) != 0) throw NpzError(where + ": not a .npy array");
  const int major = bytes[6];
  std::size_t header_len, offset;
  if (major == 1) {
    header_len = bytes[8] | (bytes[9] << 8);
    offset = 10;
  } else {
    if (bytes.size() < 12) throw NpzError(where + ": truncated .npy header");
    header_len = bytes[8] | (bytes[9] << 8) | (bytes[10] << 16) | (static_cast<std::size_t>(bytes[11]) << 24);
    offset = 12;
  }
  if (offset + header_len > bytes.size()) throw NpzError(where + ": truncated .npy header");
  const std::string header(bytes.begin() + static_cast<long>(offset),
                           bytes.begin() + static_cast<long>(offset + header_len));
  std::smatch m;
  if (!std::regex_search(header, m, std::regex("'descr':\\s*'([<>|=]?)([fi])(\\d)'"))) {
    throw NpzError(where + ": unsupported dtype (float32/64 and int32/64 only): " + header);
  }
  const bool big_endian = m[1] == ">";
  const char kind = m[2].str()[0];
  const int width = std::stoi(m[3]);
  if (big_endian || (width != 4 && width != 8)) throw NpzError(where + ": unsupported dtype " + m[0].str());
  if (std::regex_search(header, std::regex("'fortran_order':\\s*True")))
    throw NpzError(where + ": Fortran-ordered arrays are not supported");
  if (!std::regex_search(header, m, std::regex("'shape':\\s*\\(([^)]*)\\)")))
    throw NpzError(where + ": no shape in the header");
  NpyArray array;
  std::size_t count = 1;
  const std::string dims = m[1];
  const std::regex number("\\d+");
  for (std::sregex_iterator it(dims.begin(), dims.end(), number), end; it != end; ++it) {
    array.shape.push_back(std::stoul(it->str()));
    count *= array.shape.back();
  }
  const std::size_t data_offset = offset + header_len;
  if (bytes.size() - data_offset < count * static_cast<std::size_t>(width)) {
    throw NpzError(where + ": truncated data (" + std::to_string(bytes.size() - data_offset) + " bytes for " +
                   std::to_string(count) + " values)");
  }
  array.data.resize(count);
  const std::uint8_t* p = bytes.data() + data_offset;
  for (std::size_t i = 0; i < count; ++i, p += width) {
    if (kind == 'f' && width == 8) {
      double v;
      std::memcpy(&v, p, 8);
      array.data[i] = v;
    } else if (kind == 'f') {
      float v;
      std::memcpy(&v, p, 4);
      array.data[i] = v;
    } else if (width == 8) {
      std::int64_t v;
      std::memcpy(&v, p, 8);
      array.data[i] = static_cast<double>(v);
    } else {
      std::int32_t v;
      std::memcpy(&v, p, 4);
      array.data[i] = v;
    }
  }
  return array;
}

// Bytes a .npy takes (header and data), from its header alone (`head`: at least its first
// kNpyHeaderRead bytes, or the whole entry if shorter); throws NpzError past kMaxNpyValues.
std::size_t npySize(const std::vector<std::uint8_t>& head, const std::string& where) {
  if (head.size() < 12 || std::memcmp(head.data(), "\x93NUMPY", 6) != 0) throw NpzError(where + ": not a .npy array");
  const int major = head[6];
  const std::size_t header_len =
      major == 1 ? (head[8] | (head[9] << 8))
                 : (head[8] | (head[9] << 8) | (head[10] << 16) | (static_cast<std::size_t>(head[11]) << 24));
  const std::size_t offset = major == 1 ? 10 : 12;
  if (offset + header_len > head.size()) {
    throw NpzError(where + ": .npy header of " + std::to_string(header_len) + " bytes (at most " +
                   std::to_string(kNpyHeaderRead - offset) + " read)");
  }
  const std::string header(head.begin() + static_cast<long>(offset),
                           head.begin() + static_cast<long>(offset + header_len));
  std::smatch m;
  if (!std::regex_search(header, m, std::regex("'descr':\\s*'[<>|=]?[fi](\\d)'"))) {
    throw NpzError(where + ": unsupported dtype (float32/64 and int32/64 only): " + header);
  }
  const std::size_t width = std::stoul(m[1]);
  if (!std::regex_search(header, m, std::regex("'shape':\\s*\\(([^)]*)\\)")))
    throw NpzError(where + ": no shape in the header");
  const std::string dims = m[1];
  std::size_t count = 1;
  const std::regex number("\\d+");
  for (std::sregex_iterator it(dims.begin(), dims.end(), number), end; it != end; ++it) {
    const std::string digits = it->str();
    const std::size_t d = digits.size() > 12 ? kMaxNpyValues + 1 : std::stoul(digits);
    if (d > kMaxNpyValues || (d > 0 && count > kMaxNpyValues / d)) {
      throw NpzError(where + ": shape (" + dims + ") is more than " + std::to_string(kMaxNpyValues) + " values");
    }
    count *= d;
  }
  return offset + header_len + count * width;
}

std::vector<std::uint8_t> toNpy(const NpyArray& a) {
  std::string shape;
  for (std::size_t d : a.shape) shape += std::to_string(d) + ", ";
  if (a.shape.size() > 1)
    shape.erase(shape.size() - 2);  // (N, 3) but (N,)
  else if (!a.shape.empty())
    shape.erase(shape.size() - 1);
  std::string header = "{'descr': '<f8', 'fortran_order': False, 'shape': (" + shape + "), }";
  // Pad so that the data starts on a 64-byte boundary, ending the header with a newline (format 1.0).
  const std::size_t total = 10 + header.size() + 1;
  header.append((64 - total % 64) % 64, ' ');
  header += '\n';
  std::vector<std::uint8_t> out = {0x93,
                                   'N',
                                   'U',
                                   'M',
                                   'P',
                                   'Y',
                                   1,
                                   0,
                                   static_cast<std::uint8_t>(header.size() & 0xFF),
                                   static_cast<std::uint8_t>(header.size() >> 8)};
  out.insert(out.end(), header.begin(), header.end());
  const auto* bytes = reinterpret_cast<const std::uint8_t*>(a.data.data());
  out.insert(out.end(), bytes, bytes + a.data.size() * sizeof(double));
  return out;
}

}  // namespace

std::map<std::string, NpyArray> readNpz(const std::string& path) {
  std::string problem;
  if (!config::checkRegularFile(path, config::kMaxTableBytes, &problem)) throw NpzError(problem);
  int error = 0;
  std::unique_ptr<zip_t, ZipCloser> archive(zip_open(path.c_str(), ZIP_RDONLY | ZIP_CHECKCONS, &error));
  if (!archive) {
    zip_error_t ze;
    zip_error_init_with_code(&ze, error);
    const std::string what = zip_error_strerror(&ze);
    zip_error_fini(&ze);
    throw NpzError(path + ": not a readable .npz (zip) archive: " + what);
  }
  std::map<std::string, NpyArray> arrays;
  const zip_int64_t entries = zip_get_num_entries(archive.get(), 0);
  for (zip_int64_t i = 0; i < entries; ++i) {
    zip_stat_t st;
    if (zip_stat_index(archive.get(), static_cast<zip_uint64_t>(i), 0, &st) != 0)
      throw NpzError(path + ": unreadable entry");
    std::string name = st.name;
    if (name.size() < 4 || name.substr(name.size() - 4) != ".npy") continue;
    std::unique_ptr<zip_file_t, FileCloser> file(zip_fopen_index(archive.get(), static_cast<zip_uint64_t>(i), 0));
    if (!file) throw NpzError(path + ": cannot open array '" + name + "': " + zip_strerror(archive.get()));
    const std::string where = path + ": array '" + name.substr(0, name.size() - 4) + "'";
    // The archive's own figure for the entry's size is not trusted with memory: the .npy header is read
    // first, and the entry must be exactly as large as the array it declares (which has a limit).
    std::vector<std::uint8_t> bytes(std::min<zip_uint64_t>(st.size, kNpyHeaderRead));
    auto read = [&](std::size_t from) {
      const zip_int64_t got = zip_fread(file.get(), bytes.data() + from, bytes.size() - from);
      if (got < 0 || static_cast<std::size_t>(got) != bytes.size() - from) {
        throw NpzError(where + " is truncated or corrupt: " + zip_file_strerror(file.get()));
      }
    };
    read(0);
    const std::size_t declared = npySize(bytes, where);
    if (declared != st.size) {
      throw NpzError(where + ": the archive says " + std::to_string(st.size) + " bytes, its header " +
                     std::to_string(declared));
    }
    const std::size_t header = bytes.size();
    bytes.resize(declared);
    read(header);
    if ((st.valid & ZIP_STAT_CRC) == 0 || crc32(0L, bytes.data(), static_cast<uInt>(bytes.size())) != st.crc) {
      throw NpzError(where + " is corrupt: its CRC-32 does not match the archive's");
    }
    name.resize(name.size() - 4);
    arrays[name] = parseNpy(bytes, where);
  }
  return arrays;
}

void writeNpz(const std::string& path, const std::map<std::string, NpyArray>& arrays) {
  int error = 0;
  std::unique_ptr<zip_t, ZipCloser> archive(zip_open(path.c_str(), ZIP_CREATE | ZIP_TRUNCATE, &error));
  if (!archive) throw NpzError(path + ": cannot create the archive");
  std::vector<std::vector<std::uint8_t>> buffers;  // must outlive zip_close
  buffers.reserve(arrays.size());
  for (const auto& [name, array] : arrays) {
    buffers.push_back(toNpy(array));
    zip_source_t* source = zip_source_buffer(archive.get(), buffers.back().data(), buffers.back().size(), 0);
    const zip_int64_t index =
        source ? zip_file_add(archive.get(), (name + ".npy").c_str(), source, ZIP_FL_OVERWRITE) : -1;
    if (index < 0) {
      if (source) zip_source_free(source);
      throw NpzError(path + ": cannot add array '" + name + "': " + zip_strerror(archive.get()));
    }
    zip_set_file_compression(archive.get(), static_cast<zip_uint64_t>(index), ZIP_CM_DEFLATE, 0);
  }
  zip_t* raw = archive.release();
  if (zip_close(raw) != 0) {
    const std::string what = zip_strerror(raw);
    zip_discard(raw);
    throw NpzError(path + ": cannot write the archive: " + what);
  }
}

const NpyArray& requireArray(const std::map<std::string, NpyArray>& arrays, const std::string& key, std::size_t columns,
                             const std::string& path) {
  auto it = arrays.find(key);
  if (it == arrays.end()) {
    std::string have;
    for (const auto& [name, a] : arrays) have += (have.empty() ? "" : ", ") + name;
    throw NpzError(path + ": missing array '" + key + "' (the file has: " + (have.empty() ? "none" : have) + ")");
  }
  const NpyArray& a = it->second;
  const bool ok = columns == 1 ? a.shape.size() == 1 : (a.shape.size() == 2 && a.shape[1] == columns);
  if (!ok) {
    std::string shape;
    for (std::size_t d : a.shape) shape += (shape.empty() ? "" : ", ") + std::to_string(d);
    throw NpzError(path + ": array '" + key + "' has shape (" + shape + "), expected " +
                   (columns == 1 ? std::string("(N,)") : "(N, " + std::to_string(columns) + ")"));
  }
  for (std::size_t i = 0; i < a.data.size(); ++i) {
    if (!std::isfinite(a.data[i])) {
      throw NpzError(path + ": array '" + key + "' row " + std::to_string(i / columns) + " is not finite");
    }
  }
  return a;
}

}  // namespace roar::track
