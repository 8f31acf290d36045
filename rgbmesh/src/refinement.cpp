// Selective refinement (section V) and random operation sequences.

#include "rgbmesh/refinement.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <limits>
#include <new>
#include <type_traits>
#include <vector>

#include "rgbmesh/canonical.hpp"
#include "rgbmesh/geometry.hpp"

namespace rgbmesh {

double LodCriterion::edge_priority(const RgbMesh&, EdgeHandle) const { return 0; }
double LodCriterion::triangle_priority(const RgbMesh&, TriangleHandle) const { return 0; }
double LodCriterion::vertex_priority(const RgbMesh&, VertexHandle) const { return 0; }
bool LodCriterion::satisfied(const RgbMesh&) const { return false; }

namespace {

// Queue entries pop by priority, then the newest first. "Newest" follows an order of pushes
// that is canonical: the elements tested together (the first fill, or the tests after one
// operation) are pushed in the order of their vertices' insertion points (the same in every
// copy of the mesh), never of the slots they happen to occupy. With split_edge's own choices
// made the same way (RgbMesh::edge_precedes), a stage's result then depends on the mesh and
// the criterion only (issue 24): the same vertices and, with the diagonals of the mesh as
// given, the same triangles, whether the mesh was refined in this process or restored from a
// file. Equal priorities pop near the last operation, as a stack would (an order by position
// alone jumps across the mesh: 3.5 times slower for a ball).
struct EdgeRef {
  std::int32_t edge, a, b;
};

struct EdgeEntry {
  EdgeRef ref;
  std::int32_t first;  // index in the first batch, or -1
};

struct VertexEntry {
  std::int32_t vertex;
};

// A double's bit pattern (for positive doubles, in the order of their values).
std::uint64_t bits_of(double x) {
  std::uint64_t bits;
  std::memcpy(&bits, &x, sizeof bits);
  return bits;
}

// A growing array of trivially copyable items that grows with realloc: glibc moves a large
// block (a mapping of its own, above the tool's 1 MB threshold) with mremap, without copying,
// where std::vector holds the old and the new block at once while it copies (the queue's peak:
// a budget's queue reached 150 MB, and doubling it briefly needed 300).
template <class T>
class ReallocArray {
  static_assert(std::is_trivially_copyable_v<T>, "moved by realloc");

 public:
  ReallocArray() = default;
  ReallocArray(const ReallocArray&) = delete;
  ReallocArray& operator=(const ReallocArray&) = delete;
  ~ReallocArray() { std::free(data_); }
  std::size_t size() const { return size_; }
  std::size_t capacity() const { return capacity_; }
  T* begin() { return data_; }
  T* end() { return data_ + size_; }
  T& operator[](std::size_t i) { return data_[i]; }
  T& front() { return data_[0]; }
  const T& front() const { return data_[0]; }
  void push_back(const T& x) {
    if (size_ == capacity_) {
      const std::size_t grown = std::max<std::size_t>(64, capacity_ + capacity_ / 2);
      void* moved = std::realloc(data_, grown * sizeof(T));
      if (moved == nullptr) throw std::bad_alloc();
      data_ = static_cast<T*>(moved);
      capacity_ = grown;
    }
    data_[size_++] = x;
  }
  void pop_back() { --size_; }
  void truncate(std::size_t n) { size_ = std::min(size_, n); }
  // Gives the memory beyond the items back where at least half of it is unused (realloc shrinks
  // a block in place; for a mapping of its own the pages past the end go back to the system).
  void shrink_if_half_unused() {
    if (size_ >= capacity_ / 2) return;
    if (size_ == 0) {
      std::free(data_);
      data_ = nullptr;
      capacity_ = 0;
      return;
    }
    if (void* moved = std::realloc(data_, size_ * sizeof(T)); moved != nullptr) {
      data_ = static_cast<T*>(moved);
      capacity_ = size_;
    }
  }

 private:
  T* data_ = nullptr;
  std::size_t size_ = 0, capacity_ = 0;
};

// A priority queue whose equal priorities pop newest first, as a heap of stacks: each stack
// holds items of one priority (newest on top, linked through one pool of nodes), and the heap
// orders the stacks by priority, then the newest stack first. A push joins the newest stack of
// its priority, found through a small cache, in O(1), where a heap of (priority, sequence)
// items would sift every new item to the top of its tied block: criteria with few distinct
// priorities (a ball's level deficits) tie nearly always, and that sifting cost a fifth of a
// ball refinement. A priority missing from the cache starts a new stack, which is newer than
// every item of that priority: the order is the same.
//
// Memory (issue 44: a budget queues every green edge, with as many priorities as lengths): a
// stack is named by its top node, which always holds the newest item (a push moves the old top
// item to a new node below it), so the heap's 16-byte entries are all a stack needs: 36 bytes
// for an item alone at its priority, 20 for one that joins a stack.
template <class Item>
class NewestFirstQueue {
 public:
  bool empty() const { return size_ == 0; }
  std::size_t size() const { return size_; }
  std::size_t bytes() const { return nodes_.capacity() * sizeof(Node) + heap_.capacity() * sizeof(Stack); }

  void push(double priority, const Item& item) {
    const std::int32_t node = new_node();
    Recent& recent = recent_[slot(priority)];
    if (recent.valid && recent.priority == priority) {
      Node& top = nodes_[static_cast<std::size_t>(recent.top)];
      nodes_[static_cast<std::size_t>(node)] = top;  // the old top item, one below
      top = {item, node};
    } else {
      nodes_[static_cast<std::size_t>(node)] = {item, -1};
      if (serial_ == std::numeric_limits<std::uint32_t>::max()) renumber_serials();
      heap_.push_back({priority, ++serial_, node});
      std::push_heap(heap_.begin(), heap_.end());
      recent = {priority, node, true};
    }
    ++size_;
  }

  // The highest priority (the queue must not be empty).
  double top_priority() const { return heap_.front().priority; }

  // The newest item of the highest priority, removed.
  Item pop() {
    const Stack stack = heap_.front();
    Node& top = nodes_[static_cast<std::size_t>(stack.top)];
    const Item item = top.item;
    const std::int32_t below = top.next;
    if (below >= 0) {
      top = nodes_[static_cast<std::size_t>(below)];
      free_node(below);
    } else {
      free_node(stack.top);
      Recent& recent = recent_[slot(stack.priority)];
      if (recent.valid && recent.top == stack.top) recent.valid = false;
      std::pop_heap(heap_.begin(), heap_.end());
      heap_.pop_back();
    }
    --size_;
    return item;
  }

 private:
  struct Node {
    Item item;
    std::int32_t next;  // the node below (or the next free node), -1: none
  };
  struct Stack {
    double priority;
    std::uint32_t serial;  // newer stacks have larger serials (renumbered before they wrap)
    std::int32_t top;
    bool operator<(const Stack& o) const { return priority != o.priority ? priority < o.priority : serial < o.serial; }
  };
  struct Recent {
    double priority = 0;
    std::int32_t top = -1;
    bool valid = false;
  };
  static std::size_t slot(double priority) {
    return static_cast<std::size_t>((bits_of(priority) * 0x9E3779B97F4A7C15ull) >> 58);  // 64 slots
  }
  std::int32_t new_node() {
    if (free_nodes_ < 0) {
      nodes_.push_back(Node{});
      return static_cast<std::int32_t>(nodes_.size() - 1);
    }
    const std::int32_t node = free_nodes_;
    free_nodes_ = nodes_[static_cast<std::size_t>(node)].next;
    return node;
  }
  void free_node(std::int32_t node) {
    nodes_[static_cast<std::size_t>(node)].next = free_nodes_;
    free_nodes_ = node;
  }
  // Serials 1..n in the stacks' order (after 2^32 stacks): the order, and so the heap, stays.
  void renumber_serials() {
    std::sort(heap_.begin(), heap_.end());
    std::uint32_t next = 0;
    for (Stack& s : heap_) s.serial = ++next;
    serial_ = next;
    std::make_heap(heap_.begin(), heap_.end());
  }
  ReallocArray<Node> nodes_;
  std::int32_t free_nodes_ = -1;
  ReallocArray<Stack> heap_;         // a max-heap of the non-empty stacks
  std::array<Recent, 64> recent_{};  // per priority digest: the newest stack seen
  std::uint32_t serial_ = 0;
  std::size_t size_ = 0;
};

// A list of queue entries (priority and edge with its ends) in the order of their pushes,
// delta-coded: each field as the zigzag varint of its difference from the previous entry's
// (the priority's bit pattern, the edge's slot, the first end's slot), the second end as its
// difference from the first. On the bunny's `--budget 3000000`: about 15 bytes an entry instead
// of 20, for the 4.17 million entries set aside that are never popped (issue 44.3).
//
// keep_if rewrites the kept entries in place, each now relative to the previous kept entry.
// That never overtakes the reading: a difference over several entries is the sum of their
// differences, and a varint of a sum is no longer than the varints of its terms together
// (one more bit at most, and each term has at least one byte).
class DeltaCodedEntries {
 public:
  std::size_t size() const { return count_; }
  std::size_t bytes() const { return bytes_.capacity(); }

  void push(double priority, const EdgeRef& ref) {
    const Fields f = fields_of(priority, ref);
    std::uint8_t buffer[kMaxEntryBytes];
    const std::size_t n = encode(f, last_, buffer);
    for (std::size_t i = 0; i < n; ++i) bytes_.push_back(buffer[i]);
    last_ = f;
    ++count_;
  }

  // Calls visit(priority, ref) for every entry, in the order of their pushes.
  template <class Visit>
  void for_each(Visit visit) {
    Fields f{};
    const std::uint8_t* at = bytes_.begin();
    for (std::size_t i = 0; i < count_; ++i) {
      at = decode(at, f);
      visit(priority_of(f), ref_of(f));
    }
  }

  void clear() {
    bytes_.truncate(0);
    bytes_.shrink_if_half_unused();
    count_ = 0;
    last_ = {};
  }

  // Keeps the entries for which keep(priority, ref) is true, in their order.
  template <class Keep>
  void keep_if(Keep keep) {
    Fields read{}, written{};
    const std::uint8_t* at = bytes_.begin();
    std::uint8_t* out = bytes_.begin();
    std::size_t kept = 0;
    for (std::size_t i = 0; i < count_; ++i) {
      at = decode(at, read);
      if (!keep(priority_of(read), ref_of(read))) continue;
      std::uint8_t buffer[kMaxEntryBytes];
      const std::size_t n = encode(read, written, buffer);
      std::memcpy(out, buffer, n);  // out + n <= at (see above)
      out += n;
      written = read;
      ++kept;
    }
    bytes_.truncate(static_cast<std::size_t>(out - bytes_.begin()));
    bytes_.shrink_if_half_unused();  // a band emptied by bring-backs is not filled again
    count_ = kept;
    last_ = written;
  }

 private:
  struct Fields {
    std::uint64_t priority;
    std::int64_t edge, a, b;
  };
  static constexpr std::size_t kMaxEntryBytes = 4 * 10;

  static Fields fields_of(double priority, const EdgeRef& ref) { return {bits_of(priority), ref.edge, ref.a, ref.b}; }
  static double priority_of(const Fields& f) {
    double p;
    std::memcpy(&p, &f.priority, sizeof p);
    return p;
  }
  static EdgeRef ref_of(const Fields& f) {
    return {static_cast<std::int32_t>(f.edge), static_cast<std::int32_t>(f.a), static_cast<std::int32_t>(f.b)};
  }
  static std::uint64_t zigzag(std::int64_t v) {
    return (static_cast<std::uint64_t>(v) << 1) ^ static_cast<std::uint64_t>(v >> 63);
  }
  static std::int64_t unzigzag(std::uint64_t u) {
    return static_cast<std::int64_t>(u >> 1) ^ -static_cast<std::int64_t>(u & 1);
  }
  static std::uint8_t* put(std::uint8_t* out, std::uint64_t u) {
    while (u >= 0x80) {
      *out++ = static_cast<std::uint8_t>(u | 0x80);
      u >>= 7;
    }
    *out++ = static_cast<std::uint8_t>(u);
    return out;
  }
  static const std::uint8_t* get(const std::uint8_t* at, std::uint64_t& u) {
    u = 0;
    for (int shift = 0;; shift += 7) {
      const std::uint8_t byte = *at++;
      u |= static_cast<std::uint64_t>(byte & 0x7F) << shift;
      if (byte < 0x80) return at;
    }
  }
  // Positive doubles' bit patterns are below 2^63, so their differences fit in an int64.
  static std::size_t encode(const Fields& f, const Fields& base, std::uint8_t* out) {
    std::uint8_t* end = put(out, zigzag(static_cast<std::int64_t>(f.priority) - static_cast<std::int64_t>(base.priority)));
    end = put(end, zigzag(f.edge - base.edge));
    end = put(end, zigzag(f.a - base.a));
    end = put(end, zigzag(f.b - f.a));
    return static_cast<std::size_t>(end - out);
  }
  static const std::uint8_t* decode(const std::uint8_t* at, Fields& f) {
    std::uint64_t u;
    at = get(at, u);
    f.priority = static_cast<std::uint64_t>(static_cast<std::int64_t>(f.priority) + unzigzag(u));
    at = get(at, u);
    f.edge += unzigzag(u);
    at = get(at, u);
    f.a += unzigzag(u);
    at = get(at, u);
    f.b = f.a + unzigzag(u);
    return at;
  }

  ReallocArray<std::uint8_t> bytes_;
  std::size_t count_ = 0;
  Fields last_{};  // the last entry pushed (or kept): the base of the next push
};

// The entries a budget sets aside (Refiner::queue_batches), in bands by their priority's binary
// exponent, each band a delta-coded list in push order (entries of equal priority share a band,
// so their order stays), with a count per 1/128 of an octave. Bringing the highest back then
// reads only the bands above the threshold, which the counts give without reading any entry:
// reading all 4 million entries twice per bring-back took a fifth of a budget's time.
class SetAsideEntries {
 public:
  SetAsideEntries() : bands_(new DeltaCodedEntries[kBands]), counts_(std::size_t{1} << kBucketBits, 0) {}
  std::size_t size() const { return count_; }
  std::size_t bytes() const {
    std::size_t b = counts_.capacity() * sizeof(std::uint32_t) + kBands * sizeof(DeltaCodedEntries);
    for (std::size_t i = 0; i < kBands; ++i) b += bands_[i].bytes();
    return b;
  }

  void push(double priority, const EdgeRef& ref) {
    const std::uint64_t bucket = bucket_of(priority);
    bands_[bucket >> kBucketsPerBandBits].push(priority, ref);
    ++counts_[bucket];
    ++count_;
  }

  // Hands over (to bring(priority, ref)) every entry at or above the lower edge of the highest
  // bucket that makes at least `wanted` entries with those above it, in push order within each
  // band; returns that edge, which every entry kept is below.
  template <class Bring>
  double bring_back(std::size_t wanted, Bring bring) {
    std::size_t taken = 0, bucket = counts_.size();
    while (bucket > 0 && taken < wanted) taken += counts_[--bucket];
    const std::uint64_t edge_bits = static_cast<std::uint64_t>(bucket) << kBucketShift;
    double edge;
    std::memcpy(&edge, &edge_bits, sizeof edge);
    const std::size_t lowest_band = bucket >> kBucketsPerBandBits;
    for (std::size_t band = kBands; band-- > lowest_band;) {
      DeltaCodedEntries& entries = bands_[band];
      if (entries.size() == 0) continue;
      if (band > lowest_band || (bucket & (kBucketsPerBand - 1)) == 0) {
        entries.for_each(bring);  // the whole band is at or above the edge
        entries.clear();
      } else {
        entries.keep_if([&](double p, const EdgeRef& ref) {
          if (p < edge) return true;
          bring(p, ref);
          return false;
        });
      }
    }
    for (std::size_t b = bucket; b < counts_.size(); ++b) counts_[b] = 0;
    count_ -= taken;
    return edge;
  }

 private:
  // Positive doubles' bit patterns, in the order of their values: 11 bits of exponent and the
  // first 7 of the mantissa name a bucket, the exponent a band.
  static constexpr int kBucketShift = 45, kBucketBits = 63 - kBucketShift, kBucketsPerBandBits = 7;
  static constexpr std::size_t kBucketsPerBand = std::size_t{1} << kBucketsPerBandBits;
  static constexpr std::size_t kBands = std::size_t{1} << (kBucketBits - kBucketsPerBandBits);
  static std::uint64_t bucket_of(double priority) { return bits_of(priority) >> kBucketShift; }

  std::unique_ptr<DeltaCodedEntries[]> bands_;
  std::vector<std::uint32_t> counts_;  // entries per bucket
  std::size_t count_ = 0;
};

// The order of two points: lexicographic on x, y, z.
bool point_less(const Vec3& p, const Vec3& q) { return p.x != q.x ? p.x < q.x : (p.y != q.y ? p.y < q.y : p.z < q.z); }

// A 64-bit digest of an edge's ends (their control points, the smaller first), which tells a
// vertex in a reused slot from the one that was there (collisions: 2^-64 per pair).
std::uint64_t ends_hash(const Vec3& low, const Vec3& high) {
  std::uint64_t h = 0x9E3779B97F4A7C15ull;
  for (const double x : {low.x, low.y, low.z, high.x, high.y, high.z}) {
    h ^= bits_of(x) + 0x9E3779B97F4A7C15ull + (h << 6) + (h >> 2);
    h *= 0xBF58476D1CE4E5B9ull;
    h ^= h >> 31;
  }
  return h;
}

// An element tested but not yet numbered and queued, with its key for the numbering: the
// digest of its ends' insertion points (an edge's, the smaller first; a vertex's, twice). Any
// order that depends on the points alone is canonical; a digest sorts faster than the points,
// and ties between different elements (2^-64 per pair) are left to chance.
template <class Entry>
struct Keyed {
  double priority;
  std::uint64_t key;
  Entry entry;
  bool operator<(const Keyed& o) const { return priority != o.priority ? priority < o.priority : key < o.key; }
};

// Unregisters an observer when the run ends, also on exceptions.
class ObserverGuard {
 public:
  ObserverGuard(RgbMesh& m, int id) : mesh_(m), id_(id) {}
  ~ObserverGuard() { mesh_.remove_observer(id_); }
  ObserverGuard(const ObserverGuard&) = delete;
  ObserverGuard& operator=(const ObserverGuard&) = delete;

 private:
  RgbMesh& mesh_;
  int id_;
};

class Refiner {
 public:
  Refiner(RgbMesh& m, const LodCriterion& c, const RefinementOptions& o) : mesh_(m), crit_(c), opt_(o) {}

  RefinementResult run() {
    // Marks computed once on the mesh as given (FieldCriterion: values by the slots of its
    // triangles and vertices) are read before anything moves; the queue finds their edges
    // again by their ends.
    const bool static_marks = !crit_.tests_new_elements();
    // A criterion that stops at a size leaves most of its queue unpopped (a budget of 3 million
    // triangles ends with 4.2 million green edges queued): later pushes are set aside until
    // the queue above them runs out (bring_back_set_aside).
    if (crit_.final_triangles() > 0) set_aside_below_ = std::numeric_limits<double>::infinity();
    if (static_marks) {
      test_everything();
      canonical_diagonals(mesh_);
    }
    // Criteria that measure the mesh read Loop points of the vertices' levels (level_point),
    // exact once a vertex's limit is known and the shown control point before. Which limits a
    // mesh has cached depends on its history (a saved and restored mesh has all of them), so
    // every limit is made known first: the criteria then see the same points in every copy.
    if (!static_marks) {
      mesh_.compute_limits();
      test_everything();
    }
    if (opt_.coarsen) {
      result_.removals += opt_.coarsen(mesh_, crit_);
    } else {
      coarsen();
    }
    reserve_for_final_size();
    refine();
    while (crit_.priorities_change_nearby() && !crit_.satisfied(mesh_) && !result_.stopped_at_memory_limit) {
      const std::uint64_t before = result_.splits;
      for (EdgeHandle e : mesh_.edges()) test_edge(e);
      for (TriangleHandle t : mesh_.triangles()) test_triangle(t);
      queue_batches();
      refine();
      if (result_.splits == before) break;
    }
    if (static_marks && result_.splits > 0) canonical_diagonals(mesh_);
    return result_;
  }

 private:
  void test_everything() {
    for (EdgeHandle e : mesh_.edges()) test_edge(e);
    for (TriangleHandle t : mesh_.triangles()) test_triangle(t);
    for (VertexHandle v : mesh_.vertices()) test_vertex(v);
    queue_batches();
  }

  // The edge of a queue entry, if it is still in the mesh as a green edge to split. Entries of
  // the first batch were queued before the coarsening and compute_limits, which free and reuse
  // vertex slots and move edges to other slots: theirs must still join vertices at the control
  // points they were queued with, found by their ends. Later entries name their edge's slot
  // unless the edge is gone (refinement frees no vertex slot).
  EdgeHandle current_edge(const EdgeEntry& entry) const {
    const VertexHandle a(entry.ref.a), b(entry.ref.b);
    EdgeHandle e(entry.ref.edge);
    const auto joins = [&](EdgeHandle f) {
      const auto& ends = mesh_.edge_vertices(f);
      return (ends[0] == a && ends[1] == b) || (ends[0] == b && ends[1] == a);
    };
    if (entry.first >= 0) {
      if (!mesh_.alive(a) || !mesh_.alive(b)) return EdgeHandle();
      const Vec3 &pa = mesh_.insertion_point(a), &pb = mesh_.insertion_point(b);
      const bool swap = point_less(pb, pa);
      if (ends_hash(swap ? pb : pa, swap ? pa : pb) != first_batch_[static_cast<std::size_t>(entry.first)])
        return EdgeHandle();
      if (!mesh_.alive(e) || !joins(e)) e = mesh_.find_edge(a, b);
    } else if (!mesh_.alive(e) || !joins(e)) {
      return EdgeHandle();
    }
    if (!e.valid() || mesh_.is_red(e) || mesh_.level(e) >= opt_.max_level) return EdgeHandle();
    return e;
  }

  void test_edge(EdgeHandle e) {
    if (mesh_.is_red(e) || mesh_.level(e) >= opt_.max_level) return;
    const double p = crit_.edge_priority(mesh_, e);
    if (p > 0) push_edge(e, p);
  }

  void test_triangle(TriangleHandle t) {
    if (mesh_.level(t) >= opt_.max_level) return;
    const double p = crit_.triangle_priority(mesh_, t);
    if (!(p > 0)) return;
    mesh_.raising_edges(t, scratch_edges_);
    for (EdgeHandle e : scratch_edges_) push_edge(e, p);
  }

  void test_vertex(VertexHandle v) {
    if (!mesh_.is_removable(v)) return;
    const double p = crit_.vertex_priority(mesh_, v);
    if (p > 0) {
      const Vec3& x = mesh_.insertion_point(v);
      vertex_batch_.push_back({p, ends_hash(x, x), {v.idx}});
    }
  }


  void push_edge(EdgeHandle e, double p) {
    const auto& ev = mesh_.edge_vertices(e);
    const Vec3 &a = mesh_.insertion_point(ev[0]), &b = mesh_.insertion_point(ev[1]);
    edge_batch_.push_back({p, point_less(b, a) ? ends_hash(b, a) : ends_hash(a, b), {{e.idx, ev[0].idx, ev[1].idx}, -1}});
  }

  // Queues the elements tested since the last call in the order of their keys (priority
  // first): among equal priorities the last queued pops first. The first batch's edges keep
  // their digests (first_batch_) to be recognised after the slots move.
  void queue_batches() {
    const bool first = !queued_before_;
    queued_before_ = true;
    std::sort(edge_batch_.begin(), edge_batch_.end());
    for (auto& keyed : edge_batch_) {
      if (first) {
        keyed.entry.first = static_cast<std::int32_t>(first_batch_.size());
        first_batch_.push_back(keyed.key);
        first_queue_.push(keyed.priority, keyed.entry);
      } else if (keyed.priority >= set_aside_below_) {
        qr_.push(keyed.priority, keyed.entry.ref);
      } else {
        set_aside_.push(keyed.priority, keyed.entry.ref);
      }
    }
    edge_batch_.clear();
    std::sort(vertex_batch_.begin(), vertex_batch_.end());
    for (const auto& keyed : vertex_batch_) qc_.push(keyed.priority, keyed.entry);
    vertex_batch_.clear();
  }

  // Whether a popped edge still needs splitting: its own priority, or a triangle it raises.
  bool still_wanted(EdgeHandle e) {
    if (!crit_.tests_new_elements()) return true;
    if (crit_.edge_priority(mesh_, e) > 0) return true;
    const int l = mesh_.level(e);
    for (TriangleHandle t : mesh_.edge_triangles(e)) {
      if (!t.valid() || mesh_.level(t) != l) continue;
      if (crit_.triangle_priority(mesh_, t) > 0) return true;
      if (mesh_.color(t) != Color::red) continue;
      for (EdgeHandle f : mesh_.triangle_edges(t)) {  // the blue sibling it would raise
        if (!mesh_.is_red(f)) continue;
        const TriangleHandle u = mesh_.other_triangle(f, t);
        if (u.valid() && mesh_.color(u) == Color::blue && crit_.triangle_priority(mesh_, u) > 0) return true;
      }
    }
    return false;
  }

  std::size_t queued_edges() const { return first_queue_.size() + qr_.size() + set_aside_.size(); }
  std::size_t queue_bytes() const {
    return first_queue_.bytes() + qr_.bytes() + qc_.bytes() +
           set_aside_.bytes();
  }

  // The next edge entry in the queue's order (highest priority, then the newest), if any. The
  // first batch is older than every later entry, so on equal priorities the later queue pops
  // first; entries set aside are all below set_aside_below_ and every later entry in qr_ at or
  // above it, so they are needed only when qr_ is empty and the first batch's best is below.
  bool pop_edge(EdgeEntry& out) {
    for (;;) {
      const bool later = !qr_.empty(), early = !first_queue_.empty();
      if (later && (!early || qr_.top_priority() >= first_queue_.top_priority())) {
        out = {qr_.pop(), -1};
        return true;
      }
      if (early && (set_aside_.size() == 0 || first_queue_.top_priority() >= set_aside_below_)) {
        out = first_queue_.pop();
        return true;
      }
      if (set_aside_.size() == 0) return false;
      bring_back_set_aside();
    }
  }

  // Moves the highest of the entries set aside to qr_, in the order of their pushes (the order
  // among equal priorities stays): about a sixteenth of the triangles the criterion still needs
  // (at least 65,536), and at most half of the entries. The half matters: every later push at
  // or above the new threshold goes to qr_, and when all were brought back at the lowest
  // priority, a budget's next million splits queued theirs there (qr_ grew to 700,000 entries).
  // The threshold is a bucket's edge (SetAsideEntries keeps the counts per bucket), so about as
  // many entries move as wanted, and only the bands above it are read.
  void bring_back_set_aside() {
    const std::size_t n = set_aside_.size();
    const double missing = static_cast<double>(crit_.final_triangles()) - static_cast<double>(mesh_.num_triangles());
    const std::size_t wanted = std::max<std::size_t>(
        1, std::min(n / 2, std::max<std::size_t>(1u << 16, static_cast<std::size_t>(std::max(0.0, missing) / 16))));
    set_aside_below_ = set_aside_.bring_back(wanted, [&](double p, const EdgeRef& ref) { qr_.push(p, ref); });
  }

  void report() {
    const std::uint64_t ops = result_.splits + result_.removals;
    if (opt_.progress && ops >= next_report_) {
      opt_.progress(ops, queued_edges() + qc_.size());
      next_report_ = ops + (1u << 16);
    }
  }

  void coarsen() {
    if (qc_.empty()) return;
    VertexStar s;
    std::vector<VertexHandle> neighbours;
    // A removal leaves a trapezoid whose diagonal depends on the removal's swap sequence, and
    // whether a neighbour is removable next depends on it: the diagonals are chosen by names
    // (canonical.hpp) from the start and after every removal, so that the greedy removals are
    // the same in every copy of the mesh. (Coarsening inserts nothing: the names stay.)
    const std::vector<VertexName> names = vertex_names(mesh_);
    canonical_diagonals(mesh_, names);
    while (!qc_.empty()) {
      const VertexEntry top = qc_.pop();
      const VertexHandle v(top.vertex);
      if (!mesh_.alive(v) || !mesh_.is_removable(v) || !(crit_.vertex_priority(mesh_, v) > 0)) {
        ++result_.skipped;
        continue;
      }
      mesh_.star(v, s);
      neighbours = s.neighbors;
      mesh_.remove_vertex(v);
      canonical_diagonals_near(mesh_, names, neighbours);
      ++result_.removals;
      // Only neighbours can become removable by a removal (section V-A).
      for (VertexHandle n : neighbours) {
        if (mesh_.alive(n)) test_vertex(n);
      }
      queue_batches();
      report();
    }
  }

  // Sizes the arrays for a criterion's known final triangle count. From Euler's relation and
  // 3T + B = 2E: an interior split adds 1 vertex, 3 edges and 2 triangles, a boundary split 1,
  // 2 and 1; the boundary's share is taken to grow as the square root of the triangles (as in
  // uniform refinement), with a margin for the splits that pass the count (forced ones).
  void reserve_for_final_size() {
    const double target = static_cast<double>(crit_.final_triangles());
    const double t = static_cast<double>(mesh_.num_triangles());
    if (!(target > t) || t == 0) return;
    const double boundary = std::max(0.0, 2.0 * static_cast<double>(mesh_.num_edges()) - 3.0 * t);
    const double more = target * 1.001 + 64 - t;
    const double more_boundary = boundary * (std::sqrt(target / t) - 1) * 1.25;
    const auto grown = [](std::size_t now, double added) { return now + static_cast<std::size_t>(std::ceil(added)); };
    const std::size_t vertices = grown(mesh_.num_vertices(), 0.5 * more + more_boundary);
    const std::size_t edges = grown(mesh_.num_edges(), 1.5 * more + more_boundary);
    const std::size_t triangles = grown(mesh_.num_triangles(), more);
    // Only when it fits under the ceiling (the refinement then stops at it instead).
    if (opt_.max_mesh_bytes != 0 &&
        static_cast<double>(MeshCounts{static_cast<double>(vertices), static_cast<double>(edges),
                                       static_cast<double>(triangles)}.bytes()) +
                static_cast<double>(mesh_.memory_bytes()) >
            static_cast<double>(opt_.max_mesh_bytes))
      return;
    mesh_.reserve(vertices, edges, triangles);
  }

  // Whether the next growth of the arrays would pass the ceiling. A growing std::vector holds
  // its old and new blocks at once, and the largest array (control points) is about a fifth of
  // the total: half again the current size covers the transient. Checked every 1024 splits.
  bool at_memory_limit() {
    if (opt_.max_mesh_bytes == 0 || (++memory_checks_ & 1023) != 0) return false;
    const double bytes = 1.5 * static_cast<double>(mesh_.memory_bytes()) +
                         static_cast<double>(queue_bytes());
    if (bytes <= static_cast<double>(opt_.max_mesh_bytes)) return false;
    result_.stopped_at_memory_limit = true;
    return true;
  }

  void refine() {
    std::vector<VertexHandle> inserted;
    const int id = mesh_.add_insertion_observer(
        [&inserted](VertexHandle v, VertexHandle, VertexHandle) { inserted.push_back(v); });
    ObserverGuard guard(mesh_, id);
    VertexStar s;
    EdgeEntry top;
    while (!crit_.satisfied(mesh_) && !at_memory_limit() && pop_edge(top)) {
      const EdgeHandle e = current_edge(top);
      if (!e.valid() || !still_wanted(e)) {
        ++result_.skipped;
        continue;
      }
      inserted.clear();
      mesh_.split_edge(e);
      // Criteria that test new elements read their shapes (a triangle in a ball): the diagonals
      // are chosen by names after every split. Marks fixed on the mesh as given (FieldCriterion)
      // split the same edges whatever the diagonals in between (forced splits follow levels,
      // which both diagonals share), so they are chosen once, at the end.
      result_.splits += inserted.size();
      if (crit_.tests_new_elements()) {
        for (VertexHandle m : inserted) {
          if (!mesh_.alive(m)) continue;
          mesh_.star(m, s);
          for (EdgeHandle f : s.edges) test_edge(f);
          for (TriangleHandle t : s.triangles) {
            test_triangle(t);
            // The far edge of a new triangle may have just become refinable.
            if (crit_.priorities_change_nearby()) {
              for (EdgeHandle f : mesh_.triangle_edges(t)) {
                const auto& fv = mesh_.edge_vertices(f);
                if (fv[0] != m && fv[1] != m) test_edge(f);
              }
            }
          }
        }
        queue_batches();
      }
      report();
    }
  }

  RgbMesh& mesh_;
  const LodCriterion& crit_;
  const RefinementOptions& opt_;
  // The queue of edges to split: the first batch's entries, the later ones at or above
  // set_aside_below_, and the later ones below it set aside in the order of their pushes.
  NewestFirstQueue<EdgeEntry> first_queue_;
  NewestFirstQueue<EdgeRef> qr_;
  SetAsideEntries set_aside_;
  double set_aside_below_ = -std::numeric_limits<double>::infinity();
  NewestFirstQueue<VertexEntry> qc_;
  std::vector<Keyed<EdgeEntry>> edge_batch_;  // tested, not yet numbered and queued
  std::vector<Keyed<VertexEntry>> vertex_batch_;
  bool queued_before_ = false;
  std::vector<std::uint64_t> first_batch_;  // ends_hash of the first batch's edges
  std::vector<EdgeHandle> scratch_edges_;
  RefinementResult result_;
  std::uint64_t next_report_ = 1u << 16;
  std::uint64_t memory_checks_ = 0;
};

}  // namespace

namespace {

// Level sweeps for the criteria that depend on levels only (UniformLevel, CoarsenAll): no
// queues; vertices and edges are visited in slot order, which keeps memory access sequential.
// The result is the one the queues give: the mesh of the unique uniform level, or the base.
class LevelSweep {
 public:
  LevelSweep(RgbMesh& m, const RefinementOptions& o) : mesh_(m), opt_(o) {}

  // Removes every vertex finer than `level`, finest first: a vertex of the finest level
  // present has no finer neighbour, so it is removable (section IV-D).
  void coarsen_to(int level) {
    for (int l = mesh_.max_level(); l > level; --l) {
      // Newest first: the reverse of the order in which a sweep inserted them.
      for (std::int32_t i = mesh_.vertex_slots() - 1; i >= 0; --i) {
        const VertexHandle v(i);
        if (!mesh_.alive(v) || mesh_.level(v) != l) continue;
        mesh_.remove_vertex(v);
        ++result_.removals;
        report();
      }
    }
  }

  // Splits every green edge coarser than `level`, coarsest first. A pass over level l splits
  // all green edges of level l; it creates edges of level l + 1 only (and coarser ones only
  // through forced splits, which find none once the coarser passes are done).
  void refine_to(int level) {
    if (opt_.max_mesh_bytes > 0 && level > mesh_.max_level() &&
        uniform_level_counts(mesh_, level).bytes() + static_cast<double>(mesh_.memory_bytes()) >
            static_cast<double>(opt_.max_mesh_bytes)) {
      // The arrays are reserved once for the final size, next to the current ones.
      result_.stopped_at_memory_limit = true;
      return;
    }
    reserve_for_uniform_mesh(level);
    for (int l = 0; l < level; ++l) {
      if (mesh_.is_uniform() && mesh_.level(EdgeHandle(0)) == l) {
        // A uniform mesh (the usual start: a base mesh, or a level of it) goes a level at a
        // time, in passes over the arrays on every core: the same mesh as the splits below.
        result_.splits += mesh_.split_all_edges();
        report();
        continue;
      }
      const std::int32_t n = mesh_.edge_slots();
      std::size_t count = 0;
      for (std::int32_t i = 0; i < n; ++i) {
        const EdgeHandle e(i);
        if (mesh_.alive(e) && !mesh_.is_red(e) && mesh_.level(e) == l) ++count;
      }
      if (count == 0) continue;
      // A 1-to-4 split of the level: one vertex per edge, two triangles and three edges more
      // per edge (about; forced splits add a few).
      mesh_.reserve(mesh_.num_vertices() + count, mesh_.num_edges() + 3 * count, mesh_.num_triangles() + 2 * count);
      for (std::int32_t i = 0; i < n; ++i) {
        const EdgeHandle e(i);
        if (mesh_.alive(e) && !mesh_.is_red(e) && mesh_.level(e) == l) split(e);
      }
    }
  }

  RefinementResult result() const { return result_; }

 private:
  void split(EdgeHandle e) {
    const std::uint64_t before = mesh_.counters().splits;
    mesh_.split_edge(e);
    result_.splits += mesh_.counters().splits - before;
    report();
  }

  // When the mesh is uniform (every edge green, at one level l0), the counts at `level` are
  // known: each level adds a vertex per edge, and has 2E + 3T edges and 4T triangles. One
  // reservation then replaces one per level, and the arrays are copied once.
  void reserve_for_uniform_mesh(int level) {
    int l0 = kMaxLevel + 1;
    for (EdgeHandle e : mesh_.edges()) {
      if (mesh_.is_red(e)) return;
      l0 = std::min(l0, mesh_.level(e));
    }
    for (EdgeHandle e : mesh_.edges()) {
      if (mesh_.level(e) != l0) return;
    }
    std::size_t v = mesh_.num_vertices(), e = mesh_.num_edges(), t = mesh_.num_triangles();
    for (int l = l0; l < level; ++l) {
      v += e;
      e = 2 * e + 3 * t;
      t *= 4;
    }
    mesh_.reserve(v, e, t);
  }

  void report() {
    const std::uint64_t ops = result_.splits + result_.removals;
    if (opt_.progress && ops >= next_report_) {
      opt_.progress(ops, 0);
      next_report_ = ops + (1u << 16);
    }
  }

  RgbMesh& mesh_;
  const RefinementOptions& opt_;
  RefinementResult result_;
  std::uint64_t next_report_ = 1u << 16;
};

}  // namespace

RefinementResult selective_refinement(RgbMesh& mesh, const LodCriterion& criterion,
                                      const RefinementOptions& options) {
  if (const auto* uniform = dynamic_cast<const UniformLevel*>(&criterion)) {
    LevelSweep sweep(mesh, options);
    sweep.coarsen_to(uniform->level());
    sweep.refine_to(std::min(uniform->level(), options.max_level));
    return sweep.result();
  }
  if (dynamic_cast<const CoarsenAll*>(&criterion) != nullptr) {
    LevelSweep sweep(mesh, options);
    sweep.coarsen_to(0);
    return sweep.result();
  }
  return Refiner(mesh, criterion, options).run();
}

double MeshCounts::bytes() const {
  // storage_bytes per element, in doubles (the counts may exceed every integer type).
  const double per_vertex = static_cast<double>(RgbMesh::storage_bytes(1, 0, 0));
  const double per_edge = static_cast<double>(RgbMesh::storage_bytes(0, 1, 0));
  const double per_triangle = static_cast<double>(RgbMesh::storage_bytes(0, 0, 1));
  return vertices * per_vertex + edges * per_edge + triangles * per_triangle;
}

MeshCounts uniform_level_counts(const RgbMesh& mesh, int level) {
  const double chi = static_cast<double>(mesh.euler_characteristic());
  double base_boundary = 0;  // boundary edges of the base = its boundary vertices
  for (VertexHandle v : mesh.vertices()) {
    if (mesh.level(v) == 0 && mesh.is_boundary(v)) base_boundary += 1;
  }
  const double base_triangles = 2.0 * (static_cast<double>(mesh.num_base_vertices()) - chi) - base_boundary;
  MeshCounts c;
  c.triangles = base_triangles * std::pow(4.0, level);
  const double boundary = base_boundary * std::pow(2.0, level);
  c.edges = (3.0 * c.triangles + boundary) / 2.0;
  c.vertices = chi + c.edges - c.triangles;
  return c;
}

// ---- built-in criteria ----------------------------------------------------------------------

namespace {

double edge_length(const RgbMesh& m, EdgeHandle e) {
  const auto& ev = m.edge_vertices(e);
  // Measured in the Loop mesh of the edge's level, which does not change while the edge
  // exists (shown points move as neighbours refine).
  const int l = m.level(e);
  return distance(m.level_point(ev[0], l), m.level_point(ev[1], l));
}

}  // namespace

double UniformLevel::edge_priority(const RgbMesh& m, EdgeHandle e) const {
  // Coarser edges first: their splits would be forced by the finer ones anyway.
  return m.level(e) < level_ ? static_cast<double>(level_ - m.level(e)) : 0.0;
}

double UniformLevel::vertex_priority(const RgbMesh& m, VertexHandle v) const {
  // Finest first: a vertex of the highest level is always removable.
  return m.level(v) > level_ ? static_cast<double>(m.level(v)) : 0.0;
}

double AtLeastLevel::triangle_priority(const RgbMesh& m, TriangleHandle t) const {
  return m.level(t) < level_ ? static_cast<double>(level_ - m.level(t)) : 0.0;
}

double BallLevel::triangle_priority(const RgbMesh& m, TriangleHandle t) const {
  if (m.level(t) >= level_) return 0.0;
  const auto c = m.triangle_vertices(t);
  const int l = m.level(t);
  if (point_triangle_distance(center_, m.level_point(c[0], l), m.level_point(c[1], l), m.level_point(c[2], l)) > radius_)
    return 0.0;
  return static_cast<double>(level_ - m.level(t));
}

double MaxEdgeLength::triangle_priority(const RgbMesh& m, TriangleHandle t) const {
  double longest = 0;
  for (EdgeHandle e : m.triangle_edges(t)) longest = std::max(longest, edge_length(m, e));
  return longest > length_ ? longest : 0.0;
}

double GeometricTolerance::deviation(const RgbMesh& m, EdgeHandle e) {
  const int l = m.level(e);
  const auto st = m.loop_stencil(e);
  const loop::OddMask mask = m.odd_mask(e);
  const Vec3 a = m.level_point(st[0], l), b = m.level_point(st[1], l);
  if (mask.opposite == 0.125 && mask.end == 0.375) {
    // |3/8 (a + b) + 1/8 (c + d) - (a + b) / 2| = |c + d - a - b| / 8.
    const Vec3 c = m.level_point(st[2], l), d = m.level_point(st[3], l);
    return norm(c + d - a - b) * 0.125;
  }
  if (mask.opposite != 0.0) {
    // A semi-sharp edge: the blend's distance from the midpoint.
    const Vec3 c = m.level_point(st[2], l), d = m.level_point(st[3], l);
    return norm((mask.end - 0.5) * (a + b) + mask.opposite * (c + d));
  }
  // Boundary and crease: how far the endpoints move from level l to l + 1 (limits of boundary
  // and crease vertices follow from their parents, so they are always available; base
  // vertices have theirs).
  double worst = 0;
  for (int i = 0; i < 2; ++i) {
    const VertexHandle v = st[i];
    const VertexRule rule = m.vertex_rule(v, l);
    if ((rule != VertexRule::crease && rule != VertexRule::corner) || !m.has_limit(v)) continue;
    worst = std::max(worst, distance(m.control_point(v, l + 1), m.control_point(v, l)));
  }
  return worst;
}

double GeometricTolerance::edge_priority(const RgbMesh& m, EdgeHandle e) const {
  // An edge next to a coarser triangle has no Loop stencil yet; it is tested once the
  // coarser triangle's own edges have split (if they need to).
  if (!m.is_refinable(e)) return 0.0;
  const double d = deviation(m, e);
  return d > tolerance_ ? d : 0.0;
}

double TriangleBudget::edge_priority(const RgbMesh& m, EdgeHandle e) const { return edge_length(m, e); }

double CoarsenAll::vertex_priority(const RgbMesh& m, VertexHandle v) const {
  return static_cast<double>(m.level(v));
}

FieldCriterion::FieldCriterion(std::vector<double> triangle_values, double refine_above,
                               std::vector<double> vertex_values, double coarsen_below)
    : triangle_values_(std::move(triangle_values)),
      refine_above_(refine_above),
      vertex_values_(std::move(vertex_values)),
      coarsen_below_(coarsen_below) {}

double FieldCriterion::triangle_priority(const RgbMesh&, TriangleHandle t) const {
  if (static_cast<std::size_t>(t.idx) >= triangle_values_.size()) return 0.0;
  const double x = triangle_values_[t.idx];
  return x > refine_above_ ? x : 0.0;
}

double FieldCriterion::vertex_priority(const RgbMesh&, VertexHandle v) const {
  if (static_cast<std::size_t>(v.idx) >= vertex_values_.size()) return 0.0;
  const double x = vertex_values_[v.idx];
  // Smallest values first; the offset keeps the priority positive at x = coarsen_below - 0.
  return x < coarsen_below_ ? (coarsen_below_ - x) + 1e-300 : 0.0;
}

// ---- random walk ------------------------------------------------------------------------------

RefinementResult random_walk(RgbMesh& mesh, std::uint64_t steps, std::uint64_t seed,
                             const RandomWalkOptions& options) {
  // mt19937_64 with plain modulo reduction: the same sequence with every standard library.
  std::mt19937_64 rng(seed);
  auto pick = [&rng](std::int32_t n) {
    return static_cast<std::int32_t>(rng() % static_cast<std::uint64_t>(n));
  };
  const std::size_t cap = options.max_triangles ? options.max_triangles : 64 * mesh.num_triangles();
  RefinementResult result;
  constexpr int kAttempts = 64;

  auto try_split = [&]() {
    for (int k = 0; k < kAttempts; ++k) {
      const EdgeHandle e(pick(mesh.edge_slots()));
      if (!mesh.alive(e) || mesh.is_red(e) || mesh.level(e) >= options.max_level) continue;
      const std::size_t before = mesh.num_vertices();
      mesh.split_edge(e);
      result.splits += mesh.num_vertices() - before;
      return true;
    }
    return false;
  };
  auto try_remove = [&]() {
    for (int k = 0; k < kAttempts; ++k) {
      const VertexHandle v(pick(mesh.vertex_slots()));
      if (!mesh.alive(v) || !mesh.is_removable(v)) continue;
      mesh.remove_vertex(v);
      ++result.removals;
      return true;
    }
    return false;
  };

  for (std::uint64_t step = 0; step < steps; ++step) {
    const bool split_first = mesh.num_triangles() < cap &&
                             static_cast<double>(rng() >> 11) * 0x1.0p-53 < options.split_probability;
    bool done = split_first ? try_split() : try_remove();
    if (!done) done = split_first ? try_remove() : (mesh.num_triangles() < cap && try_split());
    if (!done) ++result.skipped;
    if (options.after_step) options.after_step(step);
  }
  return result;
}

}  // namespace rgbmesh
