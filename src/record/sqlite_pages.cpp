#include "sqlite_pages.hpp"
#include "sqlite_varint.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstring>
#include <string_view>
#include <system_error>

namespace rangekit::record::sqlite_pages {
namespace {

constexpr std::size_t header_size = 100;
constexpr std::uint8_t interior_table = 0x05;
constexpr std::uint8_t leaf_table = 0x0D;
// SQLite itself refuses trees deeper than 20; a deeper one here is damage.
constexpr std::size_t max_depth = 40;

std::uint32_t big_endian(const std::uint8_t* bytes, int count) {
  std::uint32_t value = 0;
  for (int i = 0; i < count; ++i) value = (value << 8U) | bytes[i];
  return value;
}

Error damaged(std::uint32_t page, const std::string& what) {
  return make_error(Errc::io, "page " + std::to_string(page) + ": " + what);
}

class MemoryPages final : public PageSource {
 public:
  MemoryPages(std::span<const std::uint8_t> bytes, Geometry geometry) : bytes_(bytes), geometry_(geometry) {}
  [[nodiscard]] const Geometry& geometry() const override { return geometry_; }
  Status read(std::uint32_t number, std::span<std::uint8_t> into) override {
    if (number == 0 || number > geometry_.page_count) return damaged(number, "beyond the end of the file");
    const std::size_t start = static_cast<std::size_t>(number - 1) * geometry_.page_size;
    std::memcpy(into.data(), bytes_.data() + start, geometry_.page_size);
    return ok_status();
  }

 private:
  std::span<const std::uint8_t> bytes_;
  Geometry geometry_;
};

// A file read through a window of consecutive pages: a table written in key order lies
// mostly in consecutive pages, so most pages come from the window, not a system call.
class FilePages final : public PageSource {
 public:
  FilePages(int descriptor, Geometry geometry) : descriptor_(descriptor), geometry_(geometry) {
    window_pages_ = std::max<std::uint32_t>(1, window_bytes / geometry_.page_size);
    window_.resize(static_cast<std::size_t>(window_pages_) * geometry_.page_size);
  }
  ~FilePages() override { ::close(descriptor_); }
  FilePages(const FilePages&) = delete;
  FilePages& operator=(const FilePages&) = delete;

  [[nodiscard]] const Geometry& geometry() const override { return geometry_; }

  Status read(std::uint32_t number, std::span<std::uint8_t> into) override {
    if (number == 0 || number > geometry_.page_count) return damaged(number, "beyond the end of the file");
    if (number < first_ || number >= first_ + loaded_) {
      if (auto status = load_window(number); !status) return status;
    }
    const std::size_t start = static_cast<std::size_t>(number - first_) * geometry_.page_size;
    std::memcpy(into.data(), window_.data() + start, geometry_.page_size);
    return ok_status();
  }

 private:
  static constexpr std::uint32_t window_bytes = 1U << 20U;

  Status load_window(std::uint32_t number) {
    const std::uint32_t count = std::min(window_pages_, geometry_.page_count - number + 1);
    const std::size_t wanted = static_cast<std::size_t>(count) * geometry_.page_size;
    const auto offset = static_cast<off_t>(number - 1) * geometry_.page_size;
    std::size_t got = 0;
    while (got < wanted) {
      const ssize_t n = ::pread(descriptor_, window_.data() + got, wanted - got, offset + static_cast<off_t>(got));
      if (n < 0 && errno == EINTR) continue;
      if (n < 0) return damaged(number, std::string("cannot be read (") + std::generic_category().message(errno) + ")");
      if (n == 0) break;
      got += static_cast<std::size_t>(n);
    }
    loaded_ = static_cast<std::uint32_t>(got / geometry_.page_size);
    first_ = number;
    if (loaded_ == 0) return damaged(number, "beyond the end of the file (was it truncated while read?)");
    return ok_status();
  }

  int descriptor_;
  Geometry geometry_;
  std::vector<std::uint8_t> window_;
  std::uint32_t window_pages_ = 1;
  std::uint32_t first_ = 0;
  std::uint32_t loaded_ = 0;
};

// One page of the descent: its bytes and the next child to visit.
struct Level {
  std::vector<std::uint8_t> bytes;
  std::uint32_t number = 0;
  std::size_t header = 0;  // offset of the b-tree page header (100 on page 1)
  std::uint32_t cells = 0;
  std::uint32_t next = 0;  // next cell (cells = the right-most pointer)
  bool leaf = false;
};

class Walker {
 public:
  Walker(PageSource& pages, const RowVisitor& visit)
      : pages_(pages),
        geometry_(pages.geometry()),
        visit_(visit),
        seen_(static_cast<std::size_t>(geometry_.page_count) + 1, false) {}

  Status run(std::uint32_t root) {
    if (auto status = enter(root); !status) return status;
    while (depth_ > 0 && !stopped_) {
      Level& level = levels_[depth_ - 1];
      if (level.leaf) {
        if (auto status = visit_leaf(level); !status) return status;
        --depth_;
        continue;
      }
      if (level.next > level.cells) {
        --depth_;
        continue;
      }
      std::uint32_t child = 0;
      if (level.next == level.cells) {
        child = big_endian(level.bytes.data() + level.header + 8, 4);
      } else {
        auto offset = cell_offset(level, level.next);
        if (!offset) return std::move(offset).error();
        if (*offset + 4 > geometry_.usable_size) return damaged(level.number, "cell past the end of the page");
        child = big_endian(level.bytes.data() + *offset, 4);
      }
      ++level.next;
      if (auto status = enter(child); !status) return status;
    }
    return ok_status();
  }

 private:
  // Reads page `number` onto the descent, checking its type and cell pointer array.
  Status enter(std::uint32_t number) {
    if (number == 0 || number > geometry_.page_count) {
      return damaged(number, "beyond the end of the file (" + std::to_string(geometry_.page_count) + " pages)");
    }
    if (seen_[number]) return damaged(number, "reached twice (a loop in the page graph)");
    seen_[number] = true;
    if (depth_ == max_depth) return damaged(number, "b-tree deeper than " + std::to_string(max_depth));
    if (levels_.size() <= depth_) levels_.emplace_back();
    Level& level = levels_[depth_];
    level.bytes.resize(geometry_.page_size);
    if (auto status = pages_.read(number, level.bytes); !status) return status;
    level.number = number;
    level.header = number == 1 ? header_size : 0;
    const std::uint8_t type = level.bytes[level.header];
    if (type != interior_table && type != leaf_table) {
      char hex[8];
      std::snprintf(hex, sizeof hex, "0x%02X", type);
      return damaged(number, std::string("type ") + hex + ", not a table b-tree page");
    }
    level.leaf = type == leaf_table;
    level.cells = big_endian(level.bytes.data() + level.header + 3, 2);
    level.next = 0;
    const std::size_t pointers = level.header + (level.leaf ? 8 : 12);
    if (pointers + 2 * static_cast<std::size_t>(level.cells) > geometry_.usable_size) {
      return damaged(number, std::to_string(level.cells) + " cells do not fit the page");
    }
    ++depth_;
    return ok_status();
  }

  [[nodiscard]] Result<std::size_t> cell_offset(const Level& level, std::uint32_t cell) const {
    const std::size_t pointers = level.header + (level.leaf ? 8 : 12);
    const std::size_t offset = big_endian(level.bytes.data() + pointers + 2 * static_cast<std::size_t>(cell), 2);
    if (offset < pointers + 2 * static_cast<std::size_t>(level.cells) || offset >= geometry_.usable_size) {
      return damaged(level.number, "cell " + std::to_string(cell) + " at offset " + std::to_string(offset) +
                                       ", outside the page's cell area");
    }
    return offset;
  }

  Status visit_leaf(const Level& level) {
    const std::uint8_t* bytes = level.bytes.data();
    const std::size_t usable = geometry_.usable_size;
    for (std::uint32_t cell = 0; cell < level.cells; ++cell) {
      auto start = cell_offset(level, cell);
      if (!start) return std::move(start).error();
      std::size_t offset = *start;
      std::uint64_t payload = 0;
      std::uint64_t key = 0;
      if (!read_varint(bytes, usable, offset, payload) || !read_varint(bytes, usable, offset, key)) {
        return damaged(level.number, "cell " + std::to_string(cell) + ": a varint runs past the end of the page");
      }
      const auto rowid = static_cast<std::int64_t>(key);
      if (any_row_ && rowid <= last_rowid_) {
        return damaged(level.number,
                       "rowid " + std::to_string(rowid) + " out of order (after " + std::to_string(last_rowid_) + ")");
      }
      any_row_ = true;
      last_rowid_ = rowid;
      const std::size_t most_local = usable - 35;  // X of the file format
      if (payload <= most_local) {
        if (offset + payload > usable) return damaged(level.number, "cell " + std::to_string(cell) + " past the page");
        if (!visit_(rowid, std::span<const std::uint8_t>(bytes + offset, static_cast<std::size_t>(payload)))) {
          stopped_ = true;
          return ok_status();
        }
        continue;
      }
      if (auto status = assemble(level, cell, offset, payload); !status) return status;
      if (!visit_(rowid, spilled_)) {
        stopped_ = true;
        return ok_status();
      }
    }
    return ok_status();
  }

  // A record larger than a page: its local part, then the overflow chain's pages.
  Status assemble(const Level& level, std::uint32_t cell, std::size_t offset, std::uint64_t payload) {
    const std::size_t usable = geometry_.usable_size;
    // A record longer than the whole file cannot be real; refuse before allocating it.
    if (payload > static_cast<std::uint64_t>(geometry_.page_count) * usable) {
      return damaged(level.number, "cell " + std::to_string(cell) + ": record of " + std::to_string(payload) +
                                       " bytes, larger than the file");
    }
    const std::size_t least = ((usable - 12) * 32 / 255) - 23;  // M
    const std::size_t most = usable - 35;                       // X
    const std::size_t spread = least + ((payload - least) % (usable - 4));
    const std::size_t local = spread <= most ? spread : least;
    if (offset + local + 4 > usable) return damaged(level.number, "cell " + std::to_string(cell) + " past the page");
    spilled_.resize(static_cast<std::size_t>(payload));
    std::memcpy(spilled_.data(), level.bytes.data() + offset, local);
    std::uint32_t next = big_endian(level.bytes.data() + offset + local, 4);
    std::size_t filled = local;
    overflow_.resize(geometry_.page_size);
    while (filled < payload) {
      if (next == 0 || next > geometry_.page_count) {
        return damaged(level.number, "cell " + std::to_string(cell) + ": overflow page " + std::to_string(next) +
                                         " beyond the file (chain ends early)");
      }
      if (seen_[next]) return damaged(next, "reached twice (a loop in the overflow chain)");
      seen_[next] = true;
      if (auto status = pages_.read(next, overflow_); !status) return status;
      const std::size_t part = std::min<std::size_t>(payload - filled, usable - 4);
      std::memcpy(spilled_.data() + filled, overflow_.data() + 4, part);
      filled += part;
      next = big_endian(overflow_.data(), 4);
    }
    return ok_status();
  }

  PageSource& pages_;
  const Geometry& geometry_;
  const RowVisitor& visit_;
  std::vector<bool> seen_;
  std::vector<Level> levels_;
  std::size_t depth_ = 0;
  std::vector<std::uint8_t> spilled_;
  std::vector<std::uint8_t> overflow_;
  bool any_row_ = false;
  bool stopped_ = false;
  std::int64_t last_rowid_ = 0;
};

}  // namespace

Result<Geometry> parse_header(std::span<const std::uint8_t> start, std::uint64_t file_size) {
  constexpr std::string_view magic("SQLite format 3\0", 16);
  if (start.size() < header_size || std::memcmp(start.data(), magic.data(), magic.size()) != 0) {
    return make_error(Errc::io, "not an SQLite 3 file (no header)");
  }
  Geometry geometry;
  const std::uint32_t size_field = big_endian(start.data() + 16, 2);
  geometry.page_size = size_field == 1 ? 65536U : size_field;
  if (geometry.page_size < 512 || (geometry.page_size & (geometry.page_size - 1)) != 0) {
    return make_error(Errc::io, "page size " + std::to_string(geometry.page_size) + " in the header is not valid");
  }
  const std::uint32_t reserved = start[20];
  geometry.usable_size = geometry.page_size - reserved;
  if (geometry.usable_size < 480) return make_error(Errc::io, "usable page size below 480 bytes");
  const auto whole_pages = file_size / geometry.page_size;
  // The header's page count holds only when written by a version that kept it (offset 92 = 24).
  const std::uint32_t counted = big_endian(start.data() + 28, 4);
  const bool count_valid = counted != 0 && big_endian(start.data() + 92, 4) == big_endian(start.data() + 24, 4);
  const std::uint64_t pages = count_valid ? std::min<std::uint64_t>(counted, whole_pages) : whole_pages;
  geometry.page_count = static_cast<std::uint32_t>(std::min<std::uint64_t>(pages, 0xFFFFFFFEU));
  geometry.text_encoding = big_endian(start.data() + 56, 4);
  return geometry;
}

Result<std::unique_ptr<PageSource>> open_file_pages(const std::string& path) {
  const int descriptor = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (descriptor < 0)
    return make_error(Errc::io, std::string("cannot open (") + std::generic_category().message(errno) + ")");
  struct stat status {};
  std::array<std::uint8_t, header_size> start{};
  if (::fstat(descriptor, &status) != 0 ||
      ::pread(descriptor, start.data(), start.size(), 0) != static_cast<ssize_t>(start.size())) {
    ::close(descriptor);
    return make_error(Errc::io, "not an SQLite 3 file (no header)");
  }
  auto geometry = parse_header(start, static_cast<std::uint64_t>(status.st_size));
  if (!geometry) {
    ::close(descriptor);
    return std::move(geometry).error();
  }
  ::posix_fadvise(descriptor, 0, 0, POSIX_FADV_SEQUENTIAL);
  return std::unique_ptr<PageSource>(std::make_unique<FilePages>(descriptor, *geometry));
}

Result<std::unique_ptr<PageSource>> memory_pages(std::span<const std::uint8_t> bytes) {
  auto geometry = parse_header(bytes, bytes.size());
  if (!geometry) return std::move(geometry).error();
  return std::unique_ptr<PageSource>(std::make_unique<MemoryPages>(bytes, *geometry));
}

Status walk_table(PageSource& pages, std::uint32_t root, const RowVisitor& visit) {
  return Walker(pages, visit).run(root);
}

}  // namespace rangekit::record::sqlite_pages
