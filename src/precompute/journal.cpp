#include "precompute/journal.hpp"

#include <cstring>
#include <fmt/format.h>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "precompute/model_identity.hpp"

namespace tactus::precompute {

namespace {

// Version 2 adds the derivatives, version 3 the torques; older journals are refused by name.
constexpr char kMagic[8] = {'T', 'C', 'S', 'P', 'J', 'N', 'L', '3'};
constexpr char kMagicVersion1[8] = {'T', 'C', 'S', 'P', 'J', 'N', 'L', '1'};
constexpr char kMagicVersion2[8] = {'T', 'C', 'S', 'P', 'J', 'N', 'L', '2'};
constexpr std::uint32_t kRecordMark = 0x52435054u;  // "TPCR"

struct Header {
  char magic[8];
  std::uint64_t model_hash;
  std::uint64_t points;
  std::uint64_t dofs;
};

/// A record: fixed part, reason bytes, displacement and its gradient (solved points: dofs and
/// 3·dofs values), checksum of it all.
struct RecordHead {
  std::uint32_t mark;
  std::uint32_t reason_bytes;
  std::uint64_t point;
  std::int64_t source;
  std::int32_t status;
  std::int32_t iterations;
  double residual;
  double seconds;
  double force[3];
  double force_gradient[9];  ///< column-major ∂force/∂x
  double torque[3];
  double torque_gradient[9];  ///< column-major ∂torque/∂x
  std::uint64_t dofs;  ///< displacement values that follow (0 unless solved)
};

SourceLocation where(const std::filesystem::path& p) { return SourceLocation{p.string(), {}, {}, {}}; }

}  // namespace

Journal Journal::create(const std::filesystem::path& path, const Space& space) {
  std::FILE* f = std::fopen(path.string().c_str(), "wb");
  if (!f) throw InputError(where(path), "cannot create the checkpoint journal");
  Header h{};
  std::memcpy(h.magic, kMagic, sizeof kMagic);
  h.model_hash = space.identity.model_hash;
  h.points = space.grid.size();
  h.dofs = static_cast<std::uint64_t>(space.displacement.rows());
  if (std::fwrite(&h, sizeof h, 1, f) != 1 || std::fflush(f) != 0) {
    std::fclose(f);
    throw InputError(where(path), "cannot write the checkpoint journal");
  }
  return Journal(f, path);
}

Journal Journal::resume(const std::filesystem::path& path, Space& space) {
  std::FILE* f = std::fopen(path.string().c_str(), "r+b");
  if (!f) throw InputError(where(path), "cannot open the checkpoint journal");
  Journal j(f, path);
  Header h{};
  if (std::fread(&h, sizeof h, 1, f) == 1 && std::memcmp(h.magic, kMagicVersion1, sizeof kMagic) == 0)
    throw InputError(where(path), "a journal of an older version (without derivatives); delete it to start over");
  if (std::memcmp(h.magic, kMagicVersion2, sizeof kMagic) == 0)
    throw InputError(where(path), "a journal of an older version (without torques); delete it to start over");
  if (std::memcmp(h.magic, kMagic, sizeof kMagic) != 0)
    throw InputError(where(path), "not a Tactus precompute journal");
  if (h.model_hash != space.identity.model_hash)
    throw InputError(where(path), "the journal belongs to another model or [precompute] settings (model hash " +
                                      hash_text(h.model_hash) + ", this scene " +
                                      hash_text(space.identity.model_hash) + "); delete it to start over");
  if (h.points != space.grid.size() || h.dofs != static_cast<std::uint64_t>(space.displacement.rows()))
    throw InputError(where(path), "the journal's grid or mesh size differs from the scene's");
  long good = static_cast<long>(sizeof h);
  std::vector<char> reason;
  VecX displacement;
  MatX gradient;
  for (;;) {
    RecordHead r{};
    if (std::fread(&r, sizeof r, 1, f) != 1) break;
    if (r.mark != kRecordMark || r.point >= h.points || r.reason_bytes > 65536 || (r.dofs != 0 && r.dofs != h.dofs) ||
        r.status < 1 || r.status > 3)
      break;
    reason.resize(r.reason_bytes);
    if (r.reason_bytes && std::fread(reason.data(), 1, reason.size(), f) != reason.size()) break;
    displacement.resize(static_cast<Eigen::Index>(r.dofs));
    if (r.dofs && std::fread(displacement.data(), sizeof(double), r.dofs, f) != r.dofs) break;
    gradient.resize(static_cast<Eigen::Index>(r.dofs), r.dofs ? 3 : 0);
    if (r.dofs && std::fread(gradient.data(), sizeof(double), 3 * r.dofs, f) != 3 * r.dofs) break;
    std::uint64_t stored = 0;
    if (std::fread(&stored, sizeof stored, 1, f) != 1) break;
    Fnv1a check;
    check.add(&r, sizeof r);
    check.add(reason.data(), reason.size());
    check.add(displacement.data(), static_cast<std::size_t>(displacement.size()) * sizeof(double));
    check.add(gradient.data(), static_cast<std::size_t>(gradient.size()) * sizeof(double));
    if (check.value() != stored) break;
    PointResult p;
    p.point = r.point;
    p.source = r.source;
    p.status = static_cast<PointStatus>(r.status);
    p.iterations = r.iterations;
    p.residual = r.residual;
    p.seconds = r.seconds;
    p.force = Vec3(r.force[0], r.force[1], r.force[2]);
    p.reason.assign(reason.begin(), reason.end());
    p.force_gradient = Eigen::Map<const Mat3>(r.force_gradient);
    p.torque = Vec3(r.torque[0], r.torque[1], r.torque[2]);
    p.torque_gradient = Eigen::Map<const Mat3>(r.torque_gradient);
    p.displacement = displacement;
    p.displacement_gradient = gradient;
    space.store(p);
    ++j.recovered_;
    good = std::ftell(f);
  }
  // Drop a record cut short by the kill, then append after the last complete one.
  std::fflush(f);
  std::error_code ec;
  std::filesystem::resize_file(path, static_cast<std::uintmax_t>(good), ec);
  if (ec) throw InputError(where(path), "cannot truncate the checkpoint journal: " + ec.message());
  std::fseek(f, good, SEEK_SET);
  return j;
}

Journal::Journal(Journal&& other) noexcept
    : file_(other.file_), path_(std::move(other.path_)), recovered_(other.recovered_) {
  other.file_ = nullptr;
}

Journal::~Journal() { close(); }

void Journal::close() {
  if (file_) std::fclose(file_);
  file_ = nullptr;
}

void Journal::append(const PointResult& p) {
  if (!file_) return;
  RecordHead r{};
  r.mark = kRecordMark;
  r.reason_bytes = static_cast<std::uint32_t>(std::min<std::size_t>(p.reason.size(), 65536));
  r.point = p.point;
  r.source = p.source;
  r.status = static_cast<std::int32_t>(p.status);
  r.iterations = p.iterations;
  r.residual = p.residual;
  r.seconds = p.seconds;
  for (int k = 0; k < 3; ++k) r.force[k] = p.force[k];
  Eigen::Map<Mat3>(r.force_gradient) = p.force_gradient;
  for (int k = 0; k < 3; ++k) r.torque[k] = p.torque[k];
  Eigen::Map<Mat3>(r.torque_gradient) = p.torque_gradient;
  const bool with_shape = p.status == PointStatus::solved;
  // A result made without derivatives (none of the solvers makes one) keeps zeros in their place.
  const bool has_gradient =
      p.displacement_gradient.rows() == p.displacement.size() && p.displacement_gradient.cols() == 3;
  const MatX none = has_gradient ? MatX() : MatX::Zero(p.displacement.size(), 3);
  const MatX& gradient = has_gradient ? p.displacement_gradient : none;
  r.dofs = with_shape ? static_cast<std::uint64_t>(p.displacement.size()) : 0;
  Fnv1a check;
  check.add(&r, sizeof r);
  check.add(p.reason.data(), r.reason_bytes);
  if (with_shape) {
    check.add(p.displacement.data(), static_cast<std::size_t>(p.displacement.size()) * sizeof(double));
    check.add(gradient.data(), static_cast<std::size_t>(gradient.size()) * sizeof(double));
  }
  const std::uint64_t sum = check.value();
  bool ok = std::fwrite(&r, sizeof r, 1, file_) == 1;
  if (r.reason_bytes) ok = ok && std::fwrite(p.reason.data(), 1, r.reason_bytes, file_) == r.reason_bytes;
  if (with_shape) {
    ok = ok && std::fwrite(p.displacement.data(), sizeof(double), r.dofs, file_) == r.dofs;
    ok = ok && std::fwrite(gradient.data(), sizeof(double), 3 * r.dofs, file_) == 3 * r.dofs;
  }
  ok = ok && std::fwrite(&sum, sizeof sum, 1, file_) == 1;
  // Flushed to the operating system: a killed process loses nothing written here.
  ok = ok && std::fflush(file_) == 0;
  if (!ok) throw InputError(where(path_), "cannot append to the checkpoint journal (disk full?)");
}

}  // namespace tactus::precompute
