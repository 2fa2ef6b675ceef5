/* The functions of the contact laws are always inlined: the force pass's block kernels
 * (src/core/pair_blocks.c) need every law in their loop to pack it, and a call keeps a
 * loop from packing (GCC made out-of-line copies of the laws once many kernels used them). */
#ifndef ADEM_CONTACT_LAW_INLINE_H
#define ADEM_CONTACT_LAW_INLINE_H

#define ADEM_LAW static inline __attribute__((always_inline))

#endif
