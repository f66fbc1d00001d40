/* clear.cl — fills a buffer of 64-bit words with one value (the empty G-buffer word).
 * A kernel rather than clEnqueueFillBuffer so simulators and checkers (Oclgrind) see the
 * words as written; one work-item per word, tail guarded.
 */
__kernel void clear_words(__global ulong* words_g, ulong value, ulong count) {
  size_t i = get_global_id(0);
  if (i < count) words_g[i] = value;
}
