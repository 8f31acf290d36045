#pragma once
// Lists by key in one array (a counting sort), for the repair's linear-time passes over a soup.

#include <cstddef>
#include <numeric>
#include <vector>

namespace rgbmesh::repair {

// The items of key k are items[start[k]] .. items[start[k + 1] - 1], in the order given.
template <class Item>
struct Buckets {
  std::vector<std::size_t> start;
  std::vector<Item> items;
};

// `each(add)` calls add(key, item) for every item, the same way each time (it is called twice:
// to count, then to place).
template <class Item, class Each>
Buckets<Item> buckets(std::size_t keys, std::size_t count, Each each) {
  Buckets<Item> out;
  out.start.assign(keys + 1, 0);
  each([&](std::size_t key, const Item&) { ++out.start[key + 1]; });
  std::partial_sum(out.start.begin(), out.start.end(), out.start.begin());
  out.items.resize(count);
  std::vector<std::size_t> next(out.start.begin(), out.start.end() - 1);
  each([&](std::size_t key, const Item& item) { out.items[next[key]++] = item; });
  return out;
}

}  // namespace rgbmesh::repair
