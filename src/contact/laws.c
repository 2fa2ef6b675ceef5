/* placeholder replaced by the contact-law table */
